// Recording options of the command line (see input_args.hpp).
#include "input_args.hpp"

#include "enum_option.hpp"

namespace dloam::app {

void add_input_options(CLI::App* cmd, InputArgs& a) {
  cmd->add_option("--topic", a.topic, "bag: the PointCloud2 or raw-packet topic (default: the only one)");
  cmd->add_option("--calibration", a.calibration,
                  "raw packets: Velodyne calibration YAML / VeloView XML, Hesai angle-correction CSV")
      ->check(CLI::ExistingFile);
  cmd->add_option(
         "--metadata", a.metadata,
         "Ouster packets: the sensor metadata JSON (default: the .json of the same name beside the file)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--returns", a.returns, "multi-return packets: strongest, last, first or all")
      ->check(CLI::IsMember(enum_names_of<ReturnMode>()));
  cmd->add_option("--cut-azimuth", a.cut_azimuth,
                  "raw packets: a scan ends where the azimuth crosses this (deg)")
      ->check(CLI::Range(0.0, 359.999999));
  cmd->add_option("--port", a.port,
                  "pcap: UDP destination port of the LiDAR data (default: found from the packets)")
      ->check(CLI::Range(1, 65535));
}

InputConfig apply_input_args(InputConfig c, const InputArgs& a) {
  if (!a.topic.empty()) c.topic = a.topic;
  if (!a.calibration.empty()) c.calibration = a.calibration;
  if (!a.metadata.empty()) c.metadata = a.metadata;
  if (!a.returns.empty()) c.returns = *enum_from_name<ReturnMode>(a.returns);  // checked by the parser
  if (a.cut_azimuth) c.cut_azimuth_deg = *a.cut_azimuth;
  if (a.port) c.port = *a.port;
  return c;
}

}  // namespace dloam::app
