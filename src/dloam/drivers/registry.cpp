// The vendor decoders (see registry.hpp). A decoder takes part when its header
// dloam/drivers/<vendor>.hpp is in the tree.
#include "dloam/drivers/registry.hpp"

#if __has_include("dloam/drivers/velodyne.hpp")
#include "dloam/drivers/velodyne.hpp"
#define DLOAM_HAS_VELODYNE 1
#endif
#if __has_include("dloam/drivers/ouster.hpp")
#include "dloam/drivers/ouster.hpp"
#define DLOAM_HAS_OUSTER 1
#endif
#if __has_include("dloam/drivers/hesai.hpp")
#include "dloam/drivers/hesai.hpp"
#define DLOAM_HAS_HESAI 1
#endif

namespace dloam::drivers {

const char* vendor_name(Vendor vendor) {
  switch (vendor) {
    case Vendor::kVelodyne:
      return "Velodyne";
    case Vendor::kOuster:
      return "Ouster";
    case Vendor::kHesai:
      return "Hesai";
    case Vendor::kUnknown:
      break;
  }
  return "unknown";
}

std::vector<std::string> available_vendors() {
  std::vector<std::string> names;
#ifdef DLOAM_HAS_VELODYNE
  names.emplace_back("Velodyne");
#endif
#ifdef DLOAM_HAS_OUSTER
  names.emplace_back("Ouster");
#endif
#ifdef DLOAM_HAS_HESAI
  names.emplace_back("Hesai");
#endif
  return names;
}

Vendor identify([[maybe_unused]] const Packet& packet) {
#ifdef DLOAM_HAS_OUSTER
  if (looks_like_ouster(packet)) return Vendor::kOuster;
#endif
#ifdef DLOAM_HAS_VELODYNE
  if (looks_like_velodyne(packet)) return Vendor::kVelodyne;
#endif
#ifdef DLOAM_HAS_HESAI
  if (looks_like_hesai(packet)) return Vendor::kHesai;
#endif
  return Vendor::kUnknown;
}

Vendor identify(const std::vector<Packet>& packets) {
  for (const Packet& p : packets) {
    const Vendor v = identify(p);
    if (v != Vendor::kUnknown) return v;
  }
  return Vendor::kUnknown;
}

std::unique_ptr<Scanner> make_scanner([[maybe_unused]] const DriverOptions& options,
                                      const std::vector<Packet>& first_packets) {
  switch (identify(first_packets)) {
#ifdef DLOAM_HAS_VELODYNE
    case Vendor::kVelodyne:
      return make_velodyne_scanner(options, first_packets);
#endif
#ifdef DLOAM_HAS_OUSTER
    case Vendor::kOuster:
      return make_ouster_scanner(options, first_packets);
#endif
#ifdef DLOAM_HAS_HESAI
    case Vendor::kHesai:
      return make_hesai_scanner(options, first_packets);
#endif
    default:
      break;
  }
  std::string decoders;
  for (const auto& n : available_vendors()) decoders += (decoders.empty() ? "" : ", ") + n;
  if (first_packets.empty()) throw InputError("no packets to decode");
  const Packet& p = first_packets.front();
  throw InputError(p.where + ": " + std::to_string(p.size) + "-byte packet" +
                   (p.port ? " on UDP port " + std::to_string(p.port) : std::string()) + " and the " +
                   std::to_string(first_packets.size() - 1) +
                   " after it are not the data packets of a known LiDAR (decoders in this build: " +
                   (decoders.empty() ? std::string("none") : decoders) + ")");
}

}  // namespace dloam::drivers
