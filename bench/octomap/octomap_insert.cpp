// Inserts the rays of a ray file into an OctoMap OcTree at z = 0, resolution 0.04 m, one
// insertPointCloud per scan (OctoMap's own once-per-scan rule: each cell updated once per
// scan, occupied wins), and prints one JSON line with the timings.
//
// Ray file (little endian): "FSRAYS01", u64 scans; per scan: f64 origin x, f64 origin y,
// u32 rays, then rays x (f64 end x, f64 end y). Every ray is a hit.
//
// Build: make (needs liboctomap-dev). Run: ./octomap_insert rays.bin [resolution]
#include <octomap/octomap.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

struct Scan {
  double ox, oy;
  std::vector<double> xy;  // end points, x y interleaved
};

static bool read_rays(const char* path, std::vector<Scan>& scans) {
  std::ifstream f(path, std::ios::binary);
  char magic[8];
  if (!f.read(magic, 8) || std::memcmp(magic, "FSRAYS01", 8) != 0) return false;
  uint64_t n = 0;
  f.read(reinterpret_cast<char*>(&n), 8);
  scans.resize(n);
  for (auto& s : scans) {
    uint32_t k = 0;
    f.read(reinterpret_cast<char*>(&s.ox), 8);
    f.read(reinterpret_cast<char*>(&s.oy), 8);
    f.read(reinterpret_cast<char*>(&k), 4);
    s.xy.resize(2 * size_t(k));
    f.read(reinterpret_cast<char*>(s.xy.data()), std::streamsize(16 * size_t(k)));
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
    std::cerr << "usage: octomap_insert RAYS.bin [resolution_m]\n";
    return 2;
  }
  const double resolution = argc > 2 ? std::stod(argv[2]) : 0.04;
  std::vector<Scan> scans;
  if (!read_rays(argv[1], scans)) {
    std::cerr << "cannot read ray file " << argv[1] << "\n";
    return 1;
  }
  std::vector<octomap::Pointcloud> clouds(scans.size());
  uint64_t rays = 0;
  for (size_t i = 0; i < scans.size(); ++i) {
    for (size_t j = 0; j < scans[i].xy.size(); j += 2)
      clouds[i].push_back(float(scans[i].xy[j]), float(scans[i].xy[j + 1]), 0.0f);
    rays += clouds[i].size();
  }
  // Cells each ray traverses (free cells plus the end cell), counted outside the timing.
  uint64_t cells = 0;
  {
    octomap::OcTree probe(resolution);
    octomap::KeyRay ray;
    for (size_t i = 0; i < scans.size(); ++i) {
      octomap::point3d origin(float(scans[i].ox), float(scans[i].oy), 0.0f);
      for (const auto& p : clouds[i]) {
        if (probe.computeRayKeys(origin, p, ray)) cells += ray.size() + 1;
      }
    }
  }
  octomap::OcTree tree(resolution);
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < scans.size(); ++i) {
    octomap::point3d origin(float(scans[i].ox), float(scans[i].oy), 0.0f);
    tree.insertPointCloud(clouds[i], origin, -1.0, false, false);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "{\"scans\": %zu, \"rays\": %llu, \"cells_traversed\": %llu, \"seconds\": %.6f, \"leaf_nodes\": %zu, "
      "\"memory_bytes\": %zu, \"peak_rss_kb\": %ld}\n",
      scans.size(), (unsigned long long)rays, (unsigned long long)cells, seconds, tree.getNumLeafNodes(),
      tree.memoryUsage(), peak_rss_kb());
  return 0;
}
