// pcap / pcapng captures through libpcap (see pcap.hpp): link layer, IPv4 / IPv6, UDP,
// IPv4 reassembly.
#include "dloam/io/pcap.hpp"

#include <pcap/pcap.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "dloam/io/bytes.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;
using detail::load_be16;
using detail::load_be32;

namespace pcap_detail {
namespace {

constexpr std::uint8_t kUdp = 17;
constexpr std::size_t kMaxIpPayload = 65535;

FrameInfo problem(FrameKind kind, std::string what) {
  FrameInfo f;
  f.kind = kind;
  f.problem = std::move(what);
  return f;
}

/// UDP header + payload at `udp` (`size` captured bytes of the IP payload).
FrameInfo decode_udp(const std::uint8_t* udp, std::size_t size, FrameInfo f) {
  if (size < 8)
    return problem(FrameKind::kMalformed, "UDP header cut short (" + std::to_string(size) + " bytes)");
  const std::size_t udp_len = load_be16(udp + 4);
  if (udp_len < 8) return problem(FrameKind::kMalformed, "UDP length " + std::to_string(udp_len) + " < 8");
  if (udp_len > size)
    return problem(FrameKind::kTruncated, "UDP length " + std::to_string(udp_len) + " but only " +
                                              std::to_string(size) + " bytes captured");
  f.kind = FrameKind::kUdp;
  f.src_port = load_be16(udp);
  f.dst_port = load_be16(udp + 2);
  f.payload = udp + 8;
  f.size = udp_len - 8;
  return f;
}

FrameInfo decode_ipv4(const std::uint8_t* ip, std::size_t avail) {
  if (avail < 20)
    return problem(FrameKind::kMalformed, "IPv4 header cut short (" + std::to_string(avail) + " bytes)");
  const std::size_t ihl = (ip[0] & 0x0Fu) * 4u;
  if (ihl < 20 || ihl > avail)
    return problem(FrameKind::kMalformed, "IPv4 header length " + std::to_string(ihl) + " invalid");
  FrameInfo f;
  f.protocol = ip[9];
  f.src_ip = load_be32(ip + 12);
  f.dst_ip = load_be32(ip + 16);
  const std::uint16_t frag = load_be16(ip + 6);
  f.more_fragments = (frag & 0x2000u) != 0;
  f.fragment_offset = static_cast<std::size_t>(frag & 0x1FFFu) * 8u;
  const std::size_t total = load_be16(ip + 2);
  if (f.more_fragments || f.fragment_offset != 0) {
    if (f.protocol != kUdp) return f;  // kNotUdp
    // A fragment's extent comes from the IP total length (nothing else gives it).
    if (total < ihl)
      return problem(FrameKind::kMalformed, "IPv4 total length " + std::to_string(total) + " < header");
    if (total > avail)
      return problem(FrameKind::kTruncated, "IPv4 fragment of " + std::to_string(total) + " bytes, only " +
                                                std::to_string(avail) + " captured");
    if (f.fragment_offset + (total - ihl) > kMaxIpPayload)
      return problem(FrameKind::kMalformed, "IPv4 fragment beyond 64 KiB");
    f.kind = FrameKind::kFragment;
    f.ip_id = load_be16(ip + 4);
    f.payload = ip + ihl;
    f.size = total - ihl;
    return f;
  }
  if (f.protocol != kUdp) return f;
  // Unfragmented: bounded by the captured bytes (and by the total length when it is smaller:
  // Ethernet padding); a total length beyond the capture is ignored, the UDP length decides.
  std::size_t end = avail;
  if (total >= ihl + 8 && total < avail) end = total;
  return decode_udp(ip + ihl, end - ihl, f);
}

FrameInfo decode_ipv6(const std::uint8_t* ip, std::size_t avail) {
  if (avail < 40)
    return problem(FrameKind::kMalformed, "IPv6 header cut short (" + std::to_string(avail) + " bytes)");
  FrameInfo f;
  f.protocol = ip[6];
  if (f.protocol != kUdp) return f;  // extension headers and fragments: not read
  return decode_udp(ip + 40, avail - 40, f);
}

FrameInfo decode_ip(const std::uint8_t* ip, std::size_t avail) {
  if (avail < 1) return problem(FrameKind::kMalformed, "no IP header");
  const int version = ip[0] >> 4;
  if (version == 4) return decode_ipv4(ip, avail);
  if (version == 6) return decode_ipv6(ip, avail);
  return problem(FrameKind::kMalformed, "IP version " + std::to_string(version));
}

FrameInfo decode_ethertype(std::uint16_t type, const std::uint8_t* p, std::size_t avail) {
  if (type == 0x0800) return decode_ipv4(p, avail);
  if (type == 0x86DD) return decode_ipv6(p, avail);
  return FrameInfo{};  // ARP, LLDP, ...: kNotUdp
}

}  // namespace

FrameInfo decode_frame(int dlt, const std::uint8_t* data, std::size_t size) {
  switch (dlt) {
    case DLT_EN10MB: {
      if (size < 14) return problem(FrameKind::kMalformed, "Ethernet header cut short");
      std::size_t off = 12;
      std::uint16_t type = load_be16(data + off);
      off += 2;
      while (type == 0x8100 || type == 0x88A8 || type == 0x9100) {  // 802.1Q / 802.1ad tags
        if (size < off + 4) return problem(FrameKind::kMalformed, "VLAN tag cut short");
        type = load_be16(data + off + 2);
        off += 4;
      }
      return decode_ethertype(type, data + off, size - off);
    }
    case DLT_LINUX_SLL:
      if (size < 16) return problem(FrameKind::kMalformed, "Linux cooked header cut short");
      return decode_ethertype(load_be16(data + 14), data + 16, size - 16);
    case DLT_LINUX_SLL2:
      if (size < 20) return problem(FrameKind::kMalformed, "Linux cooked v2 header cut short");
      return decode_ethertype(load_be16(data), data + 20, size - 20);
    case DLT_RAW:
    case DLT_IPV4:
    case DLT_IPV6:
      return decode_ip(data, size);
    case DLT_NULL:
    case DLT_LOOP: {
      if (size < 4) return problem(FrameKind::kMalformed, "loopback header cut short");
      // Address family, host byte order of the capturing machine (DLT_NULL) or big-endian (DLT_LOOP).
      const std::uint32_t be = load_be32(data), le = detail::load_le<std::uint32_t>(data);
      const auto is = [&](std::uint32_t v) { return be == v || le == v; };
      if (is(2)) return decode_ipv4(data + 4, size - 4);
      if (is(24) || is(28) || is(30)) return decode_ipv6(data + 4, size - 4);
      return FrameInfo{};
    }
    default:
      return problem(FrameKind::kMalformed, "unsupported link type " + std::to_string(dlt));
  }
}

bool Reassembler::add(const FrameInfo& fragment, double time, std::vector<std::uint8_t>& datagram,
                      std::size_t& dropped) {
  for (auto it = pending_.begin(); it != pending_.end();) {  // give up on old ones
    if (time - it->second.first_time > options_.fragment_timeout_s || time < it->second.first_time - 1.0) {
      it = pending_.erase(it);
      ++dropped;
    } else {
      ++it;
    }
  }
  const Key key{fragment.src_ip, fragment.dst_ip, fragment.ip_id, fragment.protocol};
  auto it = pending_.find(key);
  if (it == pending_.end()) {
    while (!pending_.empty() && pending_.size() >= std::max<std::size_t>(1, options_.max_pending_fragments)) {
      auto oldest = std::min_element(pending_.begin(), pending_.end(), [](const auto& a, const auto& b) {
        return a.second.order < b.second.order;
      });
      pending_.erase(oldest);
      ++dropped;
    }
    Pending p;
    p.first_time = time;
    p.order = counter_++;
    it = pending_.emplace(key, std::move(p)).first;
  }
  Pending& p = it->second;
  const std::size_t begin = fragment.fragment_offset, end = begin + fragment.size;
  if (p.bytes.size() < end) p.bytes.resize(end);
  std::copy(fragment.payload, fragment.payload + fragment.size, p.bytes.begin() + static_cast<long>(begin));
  if (!fragment.more_fragments) p.total = end;
  if (end > begin) {
    p.covered.emplace_back(begin, end);
    std::sort(p.covered.begin(), p.covered.end());
    std::vector<std::pair<std::size_t, std::size_t>> merged;
    for (const auto& r : p.covered) {
      if (!merged.empty() && r.first <= merged.back().second)
        merged.back().second = std::max(merged.back().second, r.second);
      else
        merged.push_back(r);
    }
    p.covered = std::move(merged);
  }
  if (p.total == 0 || p.covered.size() != 1 || p.covered[0].first != 0 || p.covered[0].second < p.total)
    return false;
  datagram.assign(p.bytes.begin(), p.bytes.begin() + static_cast<long>(p.total));
  pending_.erase(it);
  return true;
}

}  // namespace pcap_detail

std::string PcapStats::describe() const {
  std::string s = std::to_string(records) + " records, " + std::to_string(udp) + " UDP datagrams";
  if (!ports.empty()) {
    s += " (ports";
    for (const auto& [port, n] : ports) s += " " + std::to_string(port) + ": " + std::to_string(n);
    s += ")";
  }
  s += ", " + std::to_string(selected) + " selected";
  if (other_port) s += ", " + std::to_string(other_port) + " to other ports";
  if (not_udp) s += ", " + std::to_string(not_udp) + " not UDP";
  if (reassembled)
    s += ", " + std::to_string(reassembled) + " reassembled from " + std::to_string(fragments) +
         " IPv4 fragments";
  if (incomplete) s += ", " + std::to_string(incomplete) + " fragmented datagrams incomplete (dropped)";
  if (truncated) s += ", " + std::to_string(truncated) + " cut short by the capture (dropped)";
  if (malformed) s += ", " + std::to_string(malformed) + " malformed (dropped)";
  if (!first_problem.empty()) s += "; first: " + first_problem;
  return s;
}

namespace {
pcap_t* as_pcap(void* h) { return static_cast<pcap_t*>(h); }

bool supported_link_type(int dlt) {
  switch (dlt) {
    case DLT_EN10MB:
    case DLT_LINUX_SLL:
    case DLT_LINUX_SLL2:
    case DLT_RAW:
    case DLT_IPV4:
    case DLT_IPV6:
    case DLT_NULL:
    case DLT_LOOP:
      return true;
    default:
      return false;
  }
}

void check_link_type(const std::string& path, pcap_t* p) {
  const int dlt = pcap_datalink(p);
  if (supported_link_type(dlt)) return;
  const char* name = pcap_datalink_val_to_name(dlt);
  pcap_close(p);
  fail(path, "link type " + std::string(name ? name : "?") + " (" + std::to_string(dlt) +
                 ") is not supported (Ethernet, Linux cooked, raw IP or loopback captures are)");
}

[[noreturn]] void fail_open(const std::string& path, const char* error) {
  fail(path, std::string("not a readable pcap or pcapng capture (libpcap: ") + error + ")");
}
}  // namespace

PcapReader::PcapReader(std::string name, PcapOptions options, void* handle, std::vector<std::uint8_t> memory)
    : path_(std::move(name)),
      options_(options),
      handle_(handle),
      dlt_(pcap_datalink(as_pcap(handle))),
      memory_(std::move(memory)),
      reassembler_(options) {}

PcapReader::PcapReader(const std::string& path, PcapOptions options)
    : path_(path), options_(options), reassembler_(options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "capture file not found");
  if (std::filesystem::file_size(path, ec) == 0) fail(path, "empty file (0 bytes), not a pcap capture");
  char err[PCAP_ERRBUF_SIZE] = {0};
  pcap_t* p = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, err);
  if (!p) fail_open(path, err);
  check_link_type(path, p);
  handle_ = p;
  dlt_ = pcap_datalink(p);
}

std::unique_ptr<PcapReader> PcapReader::from_memory(std::vector<std::uint8_t> bytes, const std::string& name,
                                                    PcapOptions options) {
  if (bytes.empty()) fail(name, "empty file (0 bytes), not a pcap capture");
  FILE* f = fmemopen(bytes.data(), bytes.size(), "rb");
  if (!f) fail(name, "cannot read the capture from memory");
  char err[PCAP_ERRBUF_SIZE] = {0};
  pcap_t* p = pcap_fopen_offline_with_tstamp_precision(f, PCAP_TSTAMP_PRECISION_NANO, err);
  if (!p) {
    std::fclose(f);
    fail_open(name, err);
  }
  check_link_type(name, p);
  return std::unique_ptr<PcapReader>(new PcapReader(name, options, p, std::move(bytes)));
}

PcapReader::~PcapReader() {
  if (handle_) pcap_close(as_pcap(handle_));
}

std::string PcapReader::where() const { return "record " + std::to_string(record_ - 1); }

void PcapReader::note(const std::string& problem) {
  if (stats_.first_problem.empty()) stats_.first_problem = where() + ": " + problem;
}

bool PcapReader::next(UdpDatagram& datagram) {
  using pcap_detail::FrameKind;
  while (!done_) {
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    const int rc = pcap_next_ex(as_pcap(handle_), &header, &data);
    if (rc == PCAP_ERROR_BREAK) {  // end of the file
      done_ = true;
      if (reassembler_.pending() > 0) {
        stats_.incomplete += reassembler_.pending();
        if (stats_.first_problem.empty())
          stats_.first_problem = "end of capture: " + std::to_string(reassembler_.pending()) +
                                 " fragmented datagrams never completed";
        reassembler_.clear();
      }
      return false;
    }
    if (rc != 1)
      fail(path_, "record " + std::to_string(record_) + ": " + pcap_geterr(as_pcap(handle_)) +
                      " (the capture is damaged or cut short)");
    ++record_;
    ++stats_.records;
    const double time =
        static_cast<double>(header->ts.tv_sec) + 1e-9 * static_cast<double>(header->ts.tv_usec);
    pcap_detail::FrameInfo f = pcap_detail::decode_frame(dlt_, data, header->caplen);
    if (f.kind == FrameKind::kFragment) {
      ++stats_.fragments;
      std::size_t dropped = 0;
      const bool complete = reassembler_.add(f, time, scratch_, dropped);
      if (dropped) {
        stats_.incomplete += dropped;
        note("a fragmented datagram never completed (" + std::to_string(dropped) + " dropped)");
      }
      if (!complete) continue;
      ++stats_.reassembled;
      pcap_detail::FrameInfo u;
      u.src_ip = f.src_ip;
      u.dst_ip = f.dst_ip;
      const std::size_t udp_len = scratch_.size() >= 8 ? load_be16(scratch_.data() + 4) : 0;
      if (udp_len < 8 || udp_len > scratch_.size()) {
        ++stats_.malformed;
        note("reassembled datagram with a bad UDP length");
        continue;
      }
      u.kind = FrameKind::kUdp;
      u.src_port = load_be16(scratch_.data());
      u.dst_port = load_be16(scratch_.data() + 2);
      u.payload = scratch_.data() + 8;
      u.size = udp_len - 8;
      f = u;
    }
    switch (f.kind) {
      case FrameKind::kNotUdp:
        ++stats_.not_udp;
        continue;
      case FrameKind::kMalformed:
        ++stats_.malformed;
        note(f.problem);
        continue;
      case FrameKind::kTruncated:
        ++stats_.truncated;
        note(f.problem);
        continue;
      case FrameKind::kFragment:
      case FrameKind::kUdp:
        break;
    }
    ++stats_.udp;
    ++stats_.ports[f.dst_port];
    if (options_.port != 0 && f.dst_port != options_.port) {
      ++stats_.other_port;
      continue;
    }
    ++stats_.selected;
    datagram.payload.assign(f.payload, f.payload + f.size);
    datagram.time = time;
    datagram.record = record_ - 1;
    datagram.index = datagram_++;
    datagram.src_ip = f.src_ip;
    datagram.dst_ip = f.dst_ip;
    datagram.src_port = f.src_port;
    datagram.dst_port = f.dst_port;
    return true;
  }
  return false;
}

std::optional<PcapPosition> PcapReader::position() const {
  if (reassembler_.pending() > 0) return std::nullopt;
  FILE* f = pcap_file(as_pcap(handle_));
  if (!f) return std::nullopt;
  const long offset = std::ftell(f);
  if (offset < 0) return std::nullopt;
  return PcapPosition{offset, record_, datagram_};
}

void PcapReader::seek(const PcapPosition& position) {
  FILE* f = pcap_file(as_pcap(handle_));
  if (!f || std::fseek(f, position.offset, SEEK_SET) != 0)
    fail(path_, "cannot seek to byte " + std::to_string(position.offset));
  record_ = position.record;
  datagram_ = position.datagram;
  reassembler_.clear();
  done_ = false;
}

}  // namespace dloam::io
