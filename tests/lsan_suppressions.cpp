// LeakSanitizer's suppressions, built into every executable of the sanitizer build (CMake adds this file to them
// when TREELEARN_SANITIZE is on). Built in rather than passed in LSAN_OPTIONS: they then hold for the test binary,
// for the treelearn processes the tests start, and for a run by hand, whatever the environment and the clone's path.
//
// Mesa and llvmpipe make one-off allocations (dispatch tables, the compiled shaders' state) that live until the
// process exits; OSMesaDestroyContext does not free them.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa\n"
         "leak:libLLVM\n"
         "leak:libgallium\n";
}
