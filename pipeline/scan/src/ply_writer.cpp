#include "handscan/scan/ply_writer.hpp"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace handscan::scan {
namespace {

// PLY binary_little_endian stores the host's bytes as they are on the little-endian targets we
// build for (x86-64, aarch64); a big-endian host would need byte swaps here.
static_assert(std::endian::native == std::endian::little,
              "PLY writer assumes a little-endian host");

template <typename T>
void put(std::string& buf, T v) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    buf.append(bytes, sizeof(T));
}

Status writeFile(const std::string& path, const std::string& header, const std::string& body) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) {
        return {StatusCode::kIoError, "PLY writer: cannot open " + path + " for writing: " +
                                          std::strerror(errno) + " (check the directory exists)"};
    }
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
    out.close();
    if (!out) {
        return {StatusCode::kIoError, "PLY writer: writing " + path + " failed (disk full?)"};
    }
    return Status::ok();
}

}  // namespace

Status writeSweepPly(const std::string& path, const Sweep& sweep) {
    std::ostringstream h;
    h << "ply\nformat binary_little_endian 1.0\n"
      << "comment handscan sweep " << sweep.index << "\n"
      << "comment frame: rig (tracking camera) frame at the sweep's first point\n"
      << "comment t0_ns " << sweep.t_start << " (host CLOCK_MONOTONIC of the first point)\n"
      << "comment t: seconds since t0\n"
      << "element vertex " << sweep.points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      << "property double t\nend_header\n";
    std::string body;
    body.reserve(sweep.points.size() * 24);
    for (const SweepPoint& p : sweep.points) {
        put(body, static_cast<float>(p.p_start.x()));
        put(body, static_cast<float>(p.p_start.y()));
        put(body, static_cast<float>(p.p_start.z()));
        put(body, p.intensity);
        put(body, toSeconds(p.t - sweep.t_start));
    }
    return writeFile(path, h.str(), body);
}

Status writeCloudPly(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
    std::ostringstream h;
    h << "ply\nformat binary_little_endian 1.0\ncomment handscan map, world frame\n"
      << "element vertex " << points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\nend_header\n";
    std::string body;
    body.reserve(points.size() * 12);
    for (const Eigen::Vector3f& p : points) {
        put(body, p.x());
        put(body, p.y());
        put(body, p.z());
    }
    return writeFile(path, h.str(), body);
}

}  // namespace handscan::scan
