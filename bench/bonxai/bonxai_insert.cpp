// Inserts the rays of a ray file into a Bonxai ProbabilisticMap at z = 0, one insertPointCloud
// per scan (Bonxai's once-per-scan rule: each cell updated once per scan, occupied wins), and
// prints one JSON line with the timings. The ray file is bench/octomap's (see
// octomap_insert.cpp): "FSRAYS01", u64 scans; per scan f64 origin x, y, u32 rays, then the
// rays' end points (f64 x, f64 y). Every ray is a hit.
//
// Bonxai is not part of this repository: build with `make BONXAI_DIR=/path/to/Bonxai` (see
// the Makefile). Run: ./bonxai_insert rays.bin [resolution_m] [max_range_m]
#include <bonxai_map/probabilistic_map.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using Point = Eigen::Vector3d;

struct Scan {
  Point origin;
  std::vector<Point> ends;
};

static bool read_rays(const char* path, std::vector<Scan>& scans) {
  std::ifstream f(path, std::ios::binary);
  char magic[8];
  if (!f.read(magic, 8) || std::memcmp(magic, "FSRAYS01", 8) != 0) return false;
  uint64_t n = 0;
  f.read(reinterpret_cast<char*>(&n), 8);
  if (!f || n > (uint64_t(1) << 32)) return false;
  scans.resize(n);
  std::vector<double> xy;
  for (auto& s : scans) {
    double ox = 0, oy = 0;
    uint32_t k = 0;
    f.read(reinterpret_cast<char*>(&ox), 8);
    f.read(reinterpret_cast<char*>(&oy), 8);
    f.read(reinterpret_cast<char*>(&k), 4);
    if (!f) return false;
    xy.resize(2 * size_t(k));
    f.read(reinterpret_cast<char*>(xy.data()), std::streamsize(16 * size_t(k)));
    s.origin = Point(ox, oy, 0.0);
    s.ends.reserve(k);
    for (size_t j = 0; j < xy.size(); j += 2) s.ends.emplace_back(xy[j], xy[j + 1], 0.0);
  }
  return bool(f);
}

static long peak_rss_kb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bonxai_insert RAYS.bin [resolution_m] [max_range_m]\n";
    return 2;
  }
  const double resolution = argc > 2 ? std::stod(argv[2]) : 0.04;
  const double max_range = argc > 3 ? std::stod(argv[3]) : 1e9;
  std::vector<Scan> scans;
  if (!read_rays(argv[1], scans)) {
    std::cerr << "cannot read ray file " << argv[1] << "\n";
    return 1;
  }
  // Rays and the cells each traverses with Bonxai's own walk (the free cells from the origin
  // plus the end cell, as octomap_insert counts them), outside the timing.
  uint64_t rays = 0, cells = 0;
  {
    Bonxai::ProbabilisticMap probe(resolution);
    std::vector<Bonxai::CoordT> ray;
    for (const auto& s : scans) {
      const auto from = probe.grid().posToCoord(s.origin.x(), s.origin.y(), s.origin.z());
      for (const auto& p : s.ends) {
        Bonxai::ComputeRay(from, probe.grid().posToCoord(p.x(), p.y(), p.z()), ray);
        cells += ray.size() + 1;
      }
      rays += s.ends.size();
    }
  }
  Bonxai::ProbabilisticMap map(resolution);
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& s : scans) map.insertPointCloud(s.ends, s.origin, max_range);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<Bonxai::CoordT> occupied, free_cells;
  map.getOccupiedVoxels(occupied);
  map.getFreeVoxels(free_cells);
  std::printf(
      "{\"scans\": %zu, \"rays\": %llu, \"cells_traversed\": %llu, \"seconds\": %.6f, "
      "\"active_cells\": %zu, \"occupied\": %zu, \"free\": %zu, \"memory_bytes\": %zu, "
      "\"peak_rss_kb\": %ld}\n",
      scans.size(), (unsigned long long)rays, (unsigned long long)cells, seconds,
      map.grid().activeCellsCount(), occupied.size(), free_cells.size(), map.grid().memUsage(),
      peak_rss_kb());
  return 0;
}
