// The vendor decoders behind one call: which vendor's data packets a recording holds (each
// decoder's looks_like_<vendor>()) and the scanner for them (make_<vendor>_scanner()).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dloam/drivers/scanner.hpp"

namespace dloam::drivers {

enum class Vendor { kUnknown, kVelodyne, kOuster, kHesai };

/// "Velodyne", "Ouster", "Hesai", "unknown".
const char* vendor_name(Vendor vendor);

/// The decoders this build has, by vendor name.
std::vector<std::string> available_vendors();

/// The vendor that claims `packet` (looks_like_<vendor>), or kUnknown.
Vendor identify(const Packet& packet);

/// The vendor of the first packet of `packets` that any decoder claims, or kUnknown.
Vendor identify(const std::vector<Packet>& packets);

/// The scanner of the vendor that claims the first packets (DriverOptions::model / calibration
/// are passed on). Throws dloam::InputError naming the first packet when no decoder claims any:
/// "<where>: ... not the data packets of a known LiDAR (decoders: Velodyne, Ouster, Hesai)".
std::unique_ptr<Scanner> make_scanner(const DriverOptions& options, const std::vector<Packet>& first_packets);

}  // namespace dloam::drivers
