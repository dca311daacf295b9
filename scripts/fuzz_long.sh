#!/usr/bin/env bash
# The long fuzz: every reader's mutation test (tests/fuzz) at TIMES its usual input count (default 50: at least
# 10^5 inputs for the reader with the fewest, the skill tree), on another stream than CI's, one reader after the other.
# Prints each reader's line (inputs, loaded, refused, failures, slowest input) and exits non-zero on any failure: a
# crash, a hang (10 s watchdog), an exception other than engine::Error, or a message that does not name the file.
# Usage: scripts/fuzz_long.sh [TIMES] [SEED]   (after scripts/setup.sh; about 10 minutes on one core at 50)
set -euo pipefail
cd "$(dirname "$0")/.."
times="${1:-50}"
seed="${2:-1}"
tests=build/treelearn_tests
[ -x "$tests" ] || { echo "fuzz_long: $tests not built (run scripts/setup.sh first)" >&2; exit 2; }
status=0
for reader in $("$tests" --gtest_list_tests --gtest_filter='Fuzz*.Mutated*' | grep -E '^Fuzz' | tr -d '.'); do
  if ! out=$(TREELEARN_FUZZ_ITERATIONS="$times" TREELEARN_FUZZ_SEED="$seed" \
    "$tests" --gtest_filter="$reader.Mutated*" 2>&1); then
    status=1
    echo "$out" | tail -20
  fi
  echo "$out" | grep '^\[ fuzz' || true
done
exit $status
