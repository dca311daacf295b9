// garden_layout.cpp — see garden_layout.h.
#include "levels/garden_layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace levels {
namespace {

using R = GardenRanges;

// the bridge: the garden's (levels/garden), 8 risers of 0.13 m x 0.35 m up, a 1 m deck, 7 down, 1.8 m wide
constexpr int kBridgeSteps = 8;
constexpr double kBridgeRise = 0.13, kBridgeRun = 0.35, kBridgeTop = 1.0, kBridgeWidth = 1.8;
constexpr double kBridgeLength = kBridgeSteps * kBridgeRun + kBridgeTop + (kBridgeSteps - 1) * kBridgeRun;
constexpr double kBridgeBeforeRiver = 1.7;  // the first riser this far west of the river (the deck over the water)
// the short staircase: 3 risers of 0.10 m x 0.60 m, a 1 m top, 2 down, 2 m wide
constexpr int kFlightSteps = 3;
constexpr double kFlightRise = 0.10, kFlightRun = 0.60, kFlightTop = 1.0, kFlightWidth = 2.0;
constexpr double kFlightLength = kFlightSteps * kFlightRun + kFlightTop + (kFlightSteps - 1) * kFlightRun;
constexpr int kTries = 400;

// a double in [0, 1) from 53 random bits (portable, unlike std::uniform_real_distribution)
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }
double mm(double v) { return std::round(v * 1000.0) / 1000.0; }
double draw(std::mt19937_64& rng, double lo, double hi) { return mm(lo + unit(rng) * (hi - lo)); }

GroundRect grown(const GroundRect& r, double dx, double dy) { return {r.x0 - dx, r.y0 - dy, r.x1 + dx, r.y1 + dy}; }
bool overlap(const GroundRect& a, const GroundRect& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}
bool inside(const GroundRect& r, double margin) {
  return r.x0 >= margin && r.y0 >= margin && r.x1 <= R::kSize - margin && r.y1 <= R::kSize - margin;
}

double bridgeStart(const GardenLayout& g) { return g.riverX - kBridgeBeforeRiver; }

// where nothing else goes: the river (and a lane beside it), the bridge with a straight run-up at either end, the
// spawn, the short staircase with room to square up at either end
std::vector<GroundRect> keepOuts(const GardenLayout& g, bool withFlight) {
  const double b0 = bridgeStart(g);
  std::vector<GroundRect> k = {
      {g.riverX - 1.2, 0.0, g.riverX + R::kRiverWidth + 1.2, g.riverTop + 1.2},
      {b0 - 6.0, g.bridgeY - 2.2, b0 + kBridgeLength + 5.0, g.bridgeY + 2.2},
      {0.0, 0.0, 7.0, 5.0},
  };
  if (withFlight) {
    const Eigen::Vector2d f = g.flightStart;
    k.push_back(
        {f.x() - 3.0, f.y() - 0.5 * kFlightWidth - 1.2, f.x() + kFlightLength + 3.0, f.y() + 0.5 * kFlightWidth + 1.2});
  }
  return k;
}

bool clear(const GroundRect& r, const std::vector<GroundRect>& out) {
  for (const GroundRect& o : out)
    if (overlap(r, o)) return false;
  return true;
}

// a point with `room` to everything: keep-outs, houses, the other points
bool freePoint(const GardenLayout& g, const Eigen::Vector2d& p, double room,
               const std::vector<Eigen::Vector2d>& others) {
  const GroundRect r{p.x() - room, p.y() - room, p.x() + room, p.y() + room};
  if (!inside(r, 0.5) || !clear(r, keepOuts(g, true))) return false;
  for (const GroundRect& h : g.houses)
    if (overlap(r, h)) return false;
  for (const Eigen::Vector2d& o : others)
    if ((o - p).norm() < 2.0 * room) return false;
  return true;
}

void box(std::ostringstream& o, const std::string& name, double cx, double cy, double cz, double sx, double sy,
         double sz, const char* colour) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "[[box]]\nname = \"%s\"\ncentre = [%.3f, %.3f, %.3f]\nsize = [%.3f, %.3f, %.3f]\ncolour = \"%s\"\n\n",
                name.c_str(), cx, cy, cz, sx, sy, sz, colour);
  o << buf;
}

void stairs(std::ostringstream& o, const std::string& name, double x, double y, int steps, double rise, double run,
            double width, double top) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "[[stairs]]\nname = \"%s\"\nstart = [%.3f, %.3f]\nsteps = %d\nrise = %.3f\nrun = %.3f\nwidth = %.3f\n"
                "top = %.3f\ndown = true\n\n",
                name.c_str(), x, y, steps, rise, run, width, top);
  o << buf;
}

}  // namespace

GardenLayout drawGardenLayout(uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x6c61796f7574ULL);
  GardenLayout g;
  g.seed = seed;
  g.riverX = draw(rng, R::kRiverXMin, R::kRiverXMax);
  g.riverTop = draw(rng, R::kRiverTopMin, R::kRiverTopMax);
  g.bridgeY = draw(rng, R::kBridgeYMin, R::kBridgeYMax);
  // the short staircase on open ground (the first place that fits; else the last tried)
  const std::vector<GroundRect> base = keepOuts(g, false);
  for (int i = 0; i < kTries; ++i) {
    g.flightStart = Eigen::Vector2d(draw(rng, 3.5, R::kSize - 3.5 - kFlightLength), draw(rng, 3.5, R::kSize - 3.5));
    const GroundRect room = keepOuts(g, true).back();
    if (inside(room, 0.5) && clear(room, base)) break;
  }
  const std::vector<GroundRect> out = keepOuts(g, true);
  // houses: the alley's pair first, then the others, kStreet apart
  auto fits = [&](const GroundRect& h, const GroundRect* except) {
    if (!inside(h, R::kWallGap) || !clear(h, out)) return false;
    for (const GroundRect& o : g.houses)
      if (&o != except && overlap(grown(h, R::kStreet, R::kStreet), o)) return false;
    return true;
  };
  const int wanted = R::kHousesMin + int(unit(rng) * (R::kHousesMax - R::kHousesMin + 1));
  for (int i = 0; i < kTries && g.houses.empty(); ++i) {
    const double w = draw(rng, R::kHouseMin, R::kHouseMax - 1.0), h = draw(rng, R::kHouseDepthMin, R::kHouseDepthMax);
    const double gap = draw(rng, R::kAlleyMin, R::kAlleyMax), w2 = draw(rng, R::kHouseMin, R::kHouseMax - 2.0);
    const double x = draw(rng, 0.0, R::kSize), y = draw(rng, 0.0, R::kSize);
    const GroundRect a{x, y, mm(x + w), mm(y + h)}, b{mm(x + w + gap), y, mm(x + w + gap + w2), mm(y + h)};
    if (fits(a, nullptr) && fits(b, nullptr)) g.houses = {a, b};
  }
  for (int i = 0; i < kTries && int(g.houses.size()) < wanted; ++i) {
    const double w = draw(rng, R::kHouseMin, R::kHouseMax), h = draw(rng, R::kHouseDepthMin, R::kHouseDepthMax);
    const double x = draw(rng, 0.0, R::kSize), y = draw(rng, 0.0, R::kSize);
    const GroundRect r{x, y, mm(x + w), mm(y + h)};
    if (fits(r, nullptr)) g.houses.push_back(r);
  }
  for (int i = 0; i < kTries && g.balls.size() < 3; ++i) {
    const Eigen::Vector2d p(draw(rng, 1.0, R::kSize - 1.0), draw(rng, 1.0, R::kSize - 1.0));
    if (freePoint(g, p, 1.0, g.balls)) g.balls.push_back(p);
  }
  for (int i = 0; i < kTries && g.coins.size() < 4; ++i) {
    const Eigen::Vector2d p(draw(rng, 1.0, R::kSize - 1.0), draw(rng, 1.0, R::kSize - 1.0));
    if (freePoint(g, p, 0.8, g.coins)) g.coins.push_back(p);
  }
  return g;
}

std::string gardenLayoutToml(const GardenLayout& g) {
  std::ostringstream o;
  o << "# A garden layout drawn from seed " << g.seed << " (levels/garden_layout.h): " << describeGardenLayout(g)
    << "\nname = \"garden-layout-" << g.seed << "\"\n"
    << "description = \"a random garden: houses, a river with a stepped bridge, a short staircase, balls\"\n"
    << "plane = \"top\"\n\n[spawn]\nposition = [3.0, 2.0]\nyaw = 0.0\n\n";
  const double s = R::kSize;
  box(o, "wall_south", 0.5 * s, -0.15, 0.5, s, 0.3, 1.0, "#8c8c8c");
  box(o, "wall_north", 0.5 * s, s + 0.15, 0.5, s, 0.3, 1.0, "#8c8c8c");
  box(o, "wall_west", -0.15, 0.5 * s, 0.5, 0.3, s + 0.6, 1.0, "#8c8c8c");
  box(o, "wall_east", s + 0.15, 0.5 * s, 0.5, 0.3, s + 0.6, 1.0, "#8c8c8c");
  for (size_t i = 0; i < g.houses.size(); ++i) {
    const GroundRect& h = g.houses[i];
    box(o, "house_" + std::to_string(i + 1), 0.5 * (h.x0 + h.x1), 0.5 * (h.y0 + h.y1), 1.5, h.x1 - h.x0, h.y1 - h.y0,
        3.0, "#b5651d");
  }
  // the river south and north of the bridge, and the bridge between railings
  const double rx = g.riverX + 0.5 * R::kRiverWidth, half = 0.5 * kBridgeWidth;
  const double south = g.bridgeY - half, north = g.bridgeY + half;
  box(o, "river_south", rx, 0.5 * south, 0.05, R::kRiverWidth, south, 0.1, "#3a7bd5");
  box(o, "river_north", rx, 0.5 * (north + g.riverTop), 0.05, R::kRiverWidth, g.riverTop - north, 0.1, "#3a7bd5");
  const double b0 = bridgeStart(g), railing = kBridgeLength - 0.05;
  box(o, "railing_south", b0 + 0.5 * railing, south - 0.05, 1.1, railing, 0.1, 2.2, "#5a5a5a");
  box(o, "railing_north", b0 + 0.5 * railing, north + 0.05, 1.1, railing, 0.1, 2.2, "#5a5a5a");
  stairs(o, "bridge", b0, g.bridgeY, kBridgeSteps, kBridgeRise, kBridgeRun, kBridgeWidth, kBridgeTop);
  stairs(o, "steps", g.flightStart.x(), g.flightStart.y(), kFlightSteps, kFlightRise, kFlightRun, kFlightWidth,
         kFlightTop);
  char buf[160];
  for (const Eigen::Vector2d& c : g.coins) {
    std::snprintf(buf, sizeof buf, "[[coin]]\ncentre = [%.3f, %.3f, 0.6]\n\n", c.x(), c.y());
    o << buf;
  }
  for (const Eigen::Vector2d& b : g.balls) {
    std::snprintf(buf, sizeof buf, "[[ball]]\nposition = [%.3f, %.3f]\n\n", b.x(), b.y());
    o << buf;
  }
  return o.str();
}

std::string describeGardenLayout(const GardenLayout& g) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "river at x %.1f to y %.1f, bridge at y %.1f, %d houses, steps at (%.1f, %.1f)",
                g.riverX, g.riverTop, g.bridgeY, int(g.houses.size()), g.flightStart.x(), g.flightStart.y());
  return buf;
}

}  // namespace levels
