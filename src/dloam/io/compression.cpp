// zstd / LZ4 frame compression (see compression.hpp), over libzstd and liblz4.
#include "dloam/io/compression.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "dloam/core/types.hpp"

namespace dloam::io::detail {

namespace {
[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

void check_size(const std::vector<std::uint8_t>& out, std::size_t expected, const std::string& where,
                const char* codec) {
  if (expected != 0 && out.size() != expected)
    fail(where, std::string(codec) + " data decompresses to " + std::to_string(out.size()) +
                    " bytes, expected " + std::to_string(expected));
}
}  // namespace

std::vector<std::uint8_t> zstd_decompress(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                          const std::string& where, std::size_t limit) {
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(ZSTD_createDStream(), ZSTD_freeDStream);
  if (!stream) fail(where, "out of memory (zstd)");
  // One byte beyond the expected size, so that a longer stream shows up as a wrong size.
  const std::size_t cap = expected != 0 ? expected + 1 : limit;
  std::vector<std::uint8_t> out(
      expected != 0 ? cap : std::min<std::size_t>(cap, std::max<std::size_t>(size * 4, 1 << 16)));
  ZSTD_inBuffer in{data, size, 0};
  std::size_t produced = 0;
  for (;;) {
    ZSTD_outBuffer o{out.data() + produced, out.size() - produced, 0};
    const std::size_t rc = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(rc)) fail(where, std::string("damaged zstd data (") + ZSTD_getErrorName(rc) + ")");
    produced += o.pos;
    if (rc == 0) {  // a frame ended
      if (in.pos == in.size) break;
      continue;  // concatenated frames
    }
    if (in.pos == in.size && o.pos < o.size) fail(where, "zstd data cut short");
    if (produced == out.size()) {
      if (out.size() >= cap)
        fail(where, "zstd data decompresses to more than " + std::to_string(cap) + " bytes");
      out.resize(std::min(cap, out.size() * 2));
    }
  }
  out.resize(produced);
  check_size(out, expected, where, "zstd");
  return out;
}

std::vector<std::uint8_t> zstd_compress(const std::uint8_t* data, std::size_t size, int level) {
  std::vector<std::uint8_t> out(ZSTD_compressBound(size));
  const std::size_t n = ZSTD_compress(out.data(), out.size(), data, size, level);
  if (ZSTD_isError(n))
    throw std::runtime_error(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

void zstd_decompress_file(const std::string& from, const std::string& to) {
  std::unique_ptr<std::FILE, decltype(&std::fclose)> in(std::fopen(from.c_str(), "rb"), std::fclose);
  if (!in) fail(from, "cannot be opened");
  std::unique_ptr<std::FILE, decltype(&std::fclose)> out(std::fopen(to.c_str(), "wb"), std::fclose);
  if (!out) fail(to, "cannot be written (decompressing " + from + ")");
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(ZSTD_createDStream(), ZSTD_freeDStream);
  std::vector<std::uint8_t> ibuf(ZSTD_DStreamInSize()), obuf(ZSTD_DStreamOutSize());
  std::size_t last = 1;
  for (;;) {
    const std::size_t got = std::fread(ibuf.data(), 1, ibuf.size(), in.get());
    if (got == 0) break;
    ZSTD_inBuffer ib{ibuf.data(), got, 0};
    while (ib.pos < ib.size) {
      ZSTD_outBuffer ob{obuf.data(), obuf.size(), 0};
      last = ZSTD_decompressStream(stream.get(), &ob, &ib);
      if (ZSTD_isError(last)) fail(from, std::string("damaged zstd data (") + ZSTD_getErrorName(last) + ")");
      if (std::fwrite(obuf.data(), 1, ob.pos, out.get()) != ob.pos) fail(to, "write failed (disk full?)");
    }
  }
  if (last != 0) fail(from, "zstd data cut short");
}

std::vector<std::uint8_t> lz4_decompress(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                         const std::string& where, std::size_t limit) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) fail(where, "out of memory (lz4)");
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw,
                                                                           LZ4F_freeDecompressionContext);
  const std::size_t cap = expected != 0 ? expected + 1 : limit;
  std::vector<std::uint8_t> out(
      expected != 0 ? cap : std::min<std::size_t>(cap, std::max<std::size_t>(size * 4, 1 << 16)));
  std::size_t produced = 0, consumed = 0;
  for (;;) {
    std::size_t out_size = out.size() - produced, in_size = size - consumed;
    const std::size_t rc =
        LZ4F_decompress(ctx.get(), out.data() + produced, &out_size, data + consumed, &in_size, nullptr);
    if (LZ4F_isError(rc)) fail(where, std::string("damaged lz4 data (") + LZ4F_getErrorName(rc) + ")");
    produced += out_size;
    consumed += in_size;
    if (rc == 0) {  // a frame ended
      if (consumed == size) break;
      continue;
    }
    if (consumed == size && out_size == 0 && in_size == 0) fail(where, "lz4 data cut short");
    if (produced == out.size()) {
      if (out.size() >= cap)
        fail(where, "lz4 data decompresses to more than " + std::to_string(cap) + " bytes");
      out.resize(std::min(cap, out.size() * 2));
    }
  }
  out.resize(produced);
  check_size(out, expected, where, "lz4");
  return out;
}

std::vector<std::uint8_t> lz4_compress(const std::uint8_t* data, std::size_t size) {
  LZ4F_preferences_t prefs{};
  prefs.frameInfo.contentSize = size;
  std::vector<std::uint8_t> out(LZ4F_compressFrameBound(size, &prefs));
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), data, size, &prefs);
  if (LZ4F_isError(n))
    throw std::runtime_error(std::string("lz4 compression failed: ") + LZ4F_getErrorName(n));
  out.resize(n);
  return out;
}

}  // namespace dloam::io::detail
