#include "gnuplot.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "dloam/core/types.hpp"
#include "dloam/io/atomic_file.hpp"

namespace dloam::app {

namespace fs = std::filesystem;

void render_png(const std::string& png_path,
                const std::function<std::string(const std::string&, const std::string&)>& make_script,
                bool announce) {
  if (std::system("gnuplot --version > /dev/null 2>&1") != 0)
    throw InputError(png_path + ": the `gnuplot` program was not found (apt install gnuplot-nox)");
  const std::string terminal =
      std::system("gnuplot -e 'set terminal pngcairo' > /dev/null 2>&1") == 0 ? "pngcairo" : "png";
  const std::string tmp_png = png_path + ".tmp";
  const fs::path out(png_path);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  static int count = 0;  // one script name per plot of the process
  const fs::path script = fs::temp_directory_path() / fmt::format("dloam-plot-{}-{}.gp", ::getpid(), ++count);
  io::write_atomic(script.string(), [&](std::ostream& s) { s << make_script(tmp_png, terminal); });
  const int status = std::system(fmt::format("gnuplot '{}' 2>&1", script.string()).c_str());
  fs::remove(script);
  if (status != 0 || !fs::exists(tmp_png)) {
    fs::remove(tmp_png);
    throw InputError(png_path + ": gnuplot failed (exit status " + std::to_string(status) + ")");
  }
  fs::rename(tmp_png, png_path);
  if (announce) fmt::print("wrote {}\n", png_path);
}

}  // namespace dloam::app
