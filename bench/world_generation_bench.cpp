// Generation time of the default world and of a 1 km corridor with the same densities.
// Usage: bench_world_generation [repetitions]. Reports the median and minimum wall time.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "worlds/world.h"

namespace {

using corridorsim::worlds::World;
using corridorsim::worlds::WorldOptions;

void Measure(const char* label, const WorldOptions& options, int repetitions) {
  std::vector<double> ms;
  std::size_t triangles = 0, plates = 0, corners = 0;
  for (int i = 0; i < repetitions; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const World world = corridorsim::worlds::Generate(options, 7);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    triangles = world.triangle_count();
    plates = world.plates.size();
    corners = world.corner_points.size();
  }
  std::sort(ms.begin(), ms.end());
  std::printf(
      "%-28s median %8.1f ms  min %8.1f ms  (%d runs; %zu triangles, %zu plates, %zu corner "
      "points)\n",
      label, ms[ms.size() / 2], ms.front(), repetitions, triangles, plates, corners);
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 9;
  const WorldOptions default_options;
  Measure("default world (55 m)", default_options, repetitions);

  // 1 km with the default world's densities of doors, plates and distractors.
  WorldOptions km = default_options;
  const double scale = 1000.0 / default_options.length_m;
  km.length_m = 1000.0;
  km.doors.count = static_cast<int>(default_options.doors.count * scale);
  km.plates.count = static_cast<int>(default_options.plates.count * scale);
  km.distractors.posters = static_cast<int>(default_options.distractors.posters * scale);
  km.distractors.notice_boards =
      static_cast<int>(default_options.distractors.notice_boards * scale);
  km.distractors.bookshelves = static_cast<int>(default_options.distractors.bookshelves * scale);
  km.distractors.cabinets = static_cast<int>(default_options.distractors.cabinets * scale);
  km.distractors.fire_extinguishers =
      static_cast<int>(default_options.distractors.fire_extinguishers * scale);
  Measure("1 km corridor", km, std::max(1, repetitions / 3));
  return 0;
}
