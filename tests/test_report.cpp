// `dloam report RUN_DIR` and `dloam run --report`: a self-contained HTML page with the four plots
// (trajectory, relative error, map, timing) and the tables, checked by decoding its embedded
// images and by rendering it in headless Chromium (a screenshot with the plots' colours).
#include <gtest/gtest.h>
#include <nettle/base64.h>
#include <png.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kData = DLOAM_KITTI_0005;
constexpr int kScans = 30;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string base64_decode(const std::string& text) {
  base64_decode_ctx ctx;
  base64_decode_init(&ctx);
  std::string out(BASE64_DECODE_LENGTH(text.size()), '\0');
  std::size_t n = out.size();
  if (!base64_decode_update(&ctx, &n, reinterpret_cast<std::uint8_t*>(out.data()), text.size(),
                            text.data()) ||
      !base64_decode_final(&ctx))
    return {};
  out.resize(n);
  return out;
}

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  ///< 4 bytes per pixel, row by row
};

/// Decodes a PNG (file bytes) to RGBA with libpng's simplified API; empty on failure.
Image decode_png(const std::string& bytes) {
  Image image;
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) return image;
  png.format = PNG_FORMAT_RGBA;
  std::vector<std::uint8_t> pixels(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr)) return image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgba = std::move(pixels);
  return image;
}

/// Fraction of the pixels with a clear colour (not white, grey or black): the plots' lines,
/// palettes and boxes; text and the page's frame are grey.
double coloured_fraction(const Image& image) {
  std::size_t coloured = 0;
  const std::size_t n = image.rgba.size() / 4;
  for (std::size_t i = 0; i < n; ++i) {
    const int r = image.rgba[4 * i], g = image.rgba[4 * i + 1], b = image.rgba[4 * i + 2];
    coloured += std::max({r, g, b}) - std::min({r, g, b}) > 60;
  }
  return n ? static_cast<double>(coloured) / static_cast<double>(n) : 0.0;
}

class Report : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(kData + "/velodyne/000000.bin")) return;
    dir_ = fs::temp_directory_path() / ("dloam_test_report_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    run_ = dloam::test::run_dloam("run " + kData + " --out " + (dir_ / "run").string() +
                                  " --config kitti-raw --report --count " + std::to_string(kScans));
  }
  static void TearDownTestSuite() {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  void SetUp() override {
    if (!fs::exists(kData + "/velodyne/000000.bin")) GTEST_SKIP() << "shared data not found: " << kData;
    ASSERT_EQ(run_.status, 0) << run_.output;
  }
  static fs::path dir_;
  static dloam::test::CliRun run_;
};
fs::path Report::dir_;
dloam::test::CliRun Report::run_;

TEST_F(Report, PageEmbedsTheFourPlotsAsImagesOfTheirOwn) {
  const fs::path page = dir_ / "run" / "report.html";
  ASSERT_TRUE(fs::exists(page)) << run_.output;
  const std::string html = read_text(page);
  // Self-contained: no link to another file or server.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  // The figures in page order, each with its image as a data URI (found by hand: std::regex
  // recurses per character and overflows the stack on megabytes of base64).
  const std::string open = "<figure class=\"plot\" id=\"";
  const std::string data = "src=\"data:image/png;base64,";
  std::vector<std::string> ids;
  for (std::size_t at = html.find(open); at != std::string::npos; at = html.find(open, at + 1)) {
    const std::size_t id_begin = at + open.size();
    const std::string id = html.substr(id_begin, html.find('"', id_begin) - id_begin);
    ids.push_back(id);
    const std::size_t img = html.find("<img ", id_begin);
    const std::size_t uri = html.find(data, img);
    ASSERT_NE(uri, std::string::npos) << id;
    ASSERT_LT(uri, html.find("</figure>", id_begin)) << id << ": its image is not a data URI";
    const std::size_t begin = uri + data.size();
    const Image image = decode_png(base64_decode(html.substr(begin, html.find('"', begin) - begin)));
    EXPECT_GE(image.width, 600) << id;
    EXPECT_GE(image.height, 300) << id;
    EXPECT_GT(coloured_fraction(image), 0.002) << id << ": a plot without coloured lines or points";
  }
  EXPECT_EQ(ids, (std::vector<std::string>{"trajectory", "relative-error", "map", "timing"}));
  // The tables: the drive has ground-truth poses and labels.
  EXPECT_NE(html.find("t_rel (KITTI devkit)"), std::string::npos);
  EXPECT_NE(html.find("<table id=\"mos\">"), std::string::npos);
  EXPECT_NE(html.find("point IoU"), std::string::npos);
  EXPECT_NE(html.find(std::to_string(kScans) + " scans"), std::string::npos);
}

TEST_F(Report, ReportCommandRewritesThePageOfARunFolder) {
  const fs::path out = dir_ / "again.html";
  const auto r = dloam::test::run_dloam("report " + (dir_ / "run").string() + " --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string html = read_text(out);
  EXPECT_NE(html.find("id=\"trajectory\""), std::string::npos);
  EXPECT_NE(html.find("id=\"timing\""), std::string::npos);
}

TEST_F(Report, HeadlessChromiumRendersThePlots) {
  const std::string chromium = DLOAM_CHROMIUM;
  if (chromium.empty()) GTEST_SKIP() << "chromium not found (Debian package chromium)";
  const fs::path page = dir_ / "run" / "report.html";
  const fs::path shot = dir_ / "screenshot.png";
  const fs::path profile = dir_ / "chromium-profile";
  const std::string common =
      " --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" + profile.string() +
      " --window-size=1400,2200 ";
  const std::string shot_cmd = chromium + common + "--screenshot=" + shot.string() + " file://" +
                               page.string() + " > " + (dir_ / "chromium.log").string() + " 2>&1";
  ASSERT_EQ(std::system(shot_cmd.c_str()), 0) << read_text(dir_ / "chromium.log");
  const Image image = decode_png(read_text(shot));
  ASSERT_EQ(image.width, 1400) << read_text(dir_ / "chromium.log");
  ASSERT_EQ(image.height, 2200);
  // The page drawn: its plots' colours cover a clear part of the screenshot (a page whose images
  // failed to decode shows text and empty frames only).
  EXPECT_GT(coloured_fraction(image), 0.01);

  // The DOM as the browser parsed it still holds the four figures.
  const std::string dom_cmd = chromium + common + "--dump-dom file://" + page.string() + " 2>/dev/null";
  FILE* pipe = popen(dom_cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string dom;
  char buf[65536];
  std::size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof(buf), pipe)) > 0) dom.append(buf, got);
  pclose(pipe);
  for (const char* id : {"trajectory", "relative-error", "map", "timing"})
    EXPECT_NE(dom.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
}

TEST(ReportShortRun, APathShorterThanEverySegmentStillGetsItsPage) {
  // 8 scans cover about 2.5 m: metrics.json has no relative error (null), the page says so.
  if (!fs::exists(kData + "/velodyne/000000.bin")) GTEST_SKIP() << "shared data not found: " << kData;
  const fs::path dir = fs::temp_directory_path() / ("dloam_test_report_short_" + std::to_string(::getpid()));
  const auto r =
      dloam::test::run_dloam("run " + kData + " --out " + dir.string() + " --config kitti-raw --count 8");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto report = dloam::test::run_dloam("report " + dir.string());
  const std::string html = read_text(dir / "report.html");
  fs::remove_all(dir);
  ASSERT_EQ(report.status, 0) << report.output;
  EXPECT_NE(html.find("id=\"relative-error\""), std::string::npos);
  EXPECT_NE(html.find("t_rel (KITTI devkit)</th><td>- %"), std::string::npos);
}

TEST(ReportErrors, AFolderWithoutARunIsNamed) {
  const fs::path dir = fs::temp_directory_path() / ("dloam_test_report_empty_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto r = dloam::test::run_dloam("report " + dir.string());
  fs::remove_all(dir);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("poses.txt: missing"), std::string::npos) << r.output;
}

}  // namespace
