// pcap / pcapng captures (VeloView, Ouster Studio, tcpdump, Wireshark) read through libpcap: the
// UDP datagrams they hold, one at a time. Link types: Ethernet (802.1Q / QinQ VLAN tags), Linux
// cooked (SLL, SLL2), raw IP, BSD loopback. IPv4 fragments are reassembled (bounded memory:
// datagrams that never complete are dropped and counted); IPv6 UDP without extension headers.
// The UDP payload length comes from the UDP header, bounded by the captured bytes: some sensors
// write a wrong IPv4 total length. Errors are dloam::InputError naming the file and the record.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace dloam::io {

/// One UDP datagram of a capture. The payload buffer is reused by PcapReader::next().
struct UdpDatagram {
  std::vector<std::uint8_t> payload;
  double time = 0.0;         ///< record time (s since the epoch) of the record that completed it
  std::size_t record = 0;    ///< 0-based index of that pcap record
  std::size_t index = 0;     ///< 0-based index among the datagrams next() returned (the selected ones)
  std::uint32_t src_ip = 0;  ///< IPv4 address (host order); 0 for IPv6
  std::uint32_t dst_ip = 0;
  std::uint16_t src_port = 0;  ///< UDP ports
  std::uint16_t dst_port = 0;
};

struct PcapOptions {
  /// Keep only datagrams to this UDP destination port; 0 = every port.
  std::uint16_t port = 0;
  /// Fragmented datagrams held at once while their fragments arrive; the oldest is dropped
  /// (counted incomplete) beyond this. With up to 64 KiB each, this bounds the memory.
  std::size_t max_pending_fragments = 64;
  /// A fragmented datagram not complete this long (record time, s) after its first fragment
  /// is dropped and counted incomplete.
  double fragment_timeout_s = 2.0;
};

/// What a capture held besides the datagrams returned (nothing is skipped silently).
struct PcapStats {
  std::size_t records = 0;      ///< pcap records read
  std::size_t udp = 0;          ///< complete UDP datagrams (any port)
  std::size_t selected = 0;     ///< ... returned by next() (the port filter)
  std::size_t other_port = 0;   ///< ... to another destination port
  std::size_t not_udp = 0;      ///< records of other protocols (ARP, TCP, ICMP, IPv6 options ...)
  std::size_t malformed = 0;    ///< records too short for their headers, bad IP headers
  std::size_t truncated = 0;    ///< datagrams cut short by the capture's snapshot length
  std::size_t fragments = 0;    ///< IPv4 fragments read
  std::size_t reassembled = 0;  ///< datagrams rebuilt from fragments
  std::size_t incomplete = 0;   ///< fragmented datagrams dropped: a fragment never came
  std::map<std::uint16_t, std::size_t> ports;  ///< complete UDP datagrams per destination port
  std::string first_problem;  ///< the first malformed / truncated / incomplete record, described
  [[nodiscard]] std::string describe() const;  ///< one line: records, datagrams, what was dropped and why
};

/// Where the reader stands between two records, to come back to with PcapReader::seek().
struct PcapPosition {
  long offset = 0;           ///< byte offset of the next record in the file
  std::size_t record = 0;    ///< index of the next record
  std::size_t datagram = 0;  ///< index the next selected datagram gets
};

namespace pcap_detail {
/// The outcome of decoding one captured frame down to UDP (exposed for tests and fuzzing).
enum class FrameKind { kUdp, kFragment, kNotUdp, kMalformed, kTruncated };
struct FrameInfo {
  FrameKind kind = FrameKind::kNotUdp;
  std::string problem;  ///< kMalformed / kTruncated: what is wrong
  std::uint32_t src_ip = 0, dst_ip = 0;
  std::uint16_t src_port = 0, dst_port = 0;
  const std::uint8_t* payload = nullptr;  ///< kUdp: the UDP payload; kFragment: the IP payload
  std::size_t size = 0;
  // kFragment only:
  std::uint16_t ip_id = 0;
  std::uint8_t protocol = 0;
  std::size_t fragment_offset = 0;  ///< bytes
  bool more_fragments = false;
};
/// Decodes one frame of link type `dlt` (libpcap DLT_* value). Never reads outside [data, data+size).
FrameInfo decode_frame(int dlt, const std::uint8_t* data, std::size_t size);

/// IPv4 reassembly keyed by (source, destination, id, protocol); fragments in any order,
/// overlaps resolved by the later fragment.
class Reassembler {
 public:
  explicit Reassembler(const PcapOptions& options) : options_(options) {}
  /// Adds a fragment; returns true and fills `datagram` (the whole IP payload) when it completes one.
  /// `dropped` counts datagrams given up (timeout, too many pending).
  bool add(const FrameInfo& fragment, double time, std::vector<std::uint8_t>& datagram, std::size_t& dropped);
  [[nodiscard]] std::size_t pending() const { return pending_.size(); }
  void clear() { pending_.clear(); }

 private:
  struct Pending {
    std::vector<std::uint8_t> bytes;
    std::vector<std::pair<std::size_t, std::size_t>> covered;  ///< sorted, merged [begin, end)
    std::size_t total = 0;                                     ///< known once the last fragment came
    double first_time = 0.0;
    std::size_t order = 0;
  };
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint16_t, std::uint8_t>;
  PcapOptions options_;
  std::map<Key, Pending> pending_;
  std::size_t counter_ = 0;
};
}  // namespace pcap_detail

class PcapReader {
 public:
  /// Opens a capture; throws InputError "<path>: not a pcap or pcapng file (...)" and the like.
  explicit PcapReader(const std::string& path, PcapOptions options = {});
  /// A capture held in memory (fuzzing, tests); `name` is used in errors.
  static std::unique_ptr<PcapReader> from_memory(std::vector<std::uint8_t> bytes, const std::string& name,
                                                 PcapOptions options = {});
  ~PcapReader();
  PcapReader(const PcapReader&) = delete;
  PcapReader& operator=(const PcapReader&) = delete;

  /// The next selected datagram; false at the end of the capture. Throws InputError
  /// "<path>: record N: ..." for a damaged file (a record cut short, a bad record header).
  bool next(UdpDatagram& datagram);

  /// Position before the next record, or nullopt while fragments are pending (a position there
  /// would lose them).
  [[nodiscard]] std::optional<PcapPosition> position() const;
  /// Continues from a position of this file (pending fragments are dropped, not counted).
  void seek(const PcapPosition& position);

  [[nodiscard]] const PcapStats& stats() const { return stats_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] int link_type() const { return dlt_; }  ///< libpcap DLT_* value

 private:
  PcapReader(std::string name, PcapOptions options, void* handle, std::vector<std::uint8_t> memory);
  void note(const std::string& problem);
  [[nodiscard]] std::string where() const;

  std::string path_;
  PcapOptions options_;
  void* handle_ = nullptr;  ///< pcap_t
  int dlt_ = 0;
  std::vector<std::uint8_t> memory_;  ///< from_memory(): the bytes behind the FILE
  PcapStats stats_;
  pcap_detail::Reassembler reassembler_;
  std::vector<std::uint8_t> scratch_;
  std::size_t record_ = 0, datagram_ = 0;
  bool done_ = false;
};

}  // namespace dloam::io
