// Runs a gnuplot script that writes one PNG, atomically (the script's output goes to a temporary
// file renamed on success). Throws InputError naming the PNG when gnuplot is missing or fails.
#pragma once

#include <functional>
#include <string>

namespace dloam::app {

/// `make_script(tmp_png, terminal)` returns the script that draws into `tmp_png` with `terminal`
/// ("pngcairo" when available, else "png"). `announce`: print "wrote <png>".
void render_png(
    const std::string& png_path,
    const std::function<std::string(const std::string& tmp_png, const std::string& terminal)>& make_script,
    bool announce = true);

}  // namespace dloam::app
