// Builds the gnuplot script of plot.hpp (multiplot: trajectories, t_rel bars, r_rel bars).
#include "dloam/eval/plot.hpp"

#include <iomanip>
#include <sstream>

namespace dloam::eval {
namespace {

/// Gnuplot string literal in single quotes (a quote is doubled).
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

void write_block(std::ostream& out, const std::string& name, const std::vector<Pose>& poses, int h, int v) {
  out << '$' << name << " << EOD\n";
  for (const Pose& pose : poses) out << pose.translation()(h) << ' ' << pose.translation()(v) << '\n';
  out << "EOD\n";
}

}  // namespace

std::string odometry_plot_script(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const std::vector<LengthError>& per_length, const PlotOptions& options) {
  const auto valid_axis = [](int a) { return a >= 0 && a <= 2; };
  if (!valid_axis(options.horizontal_axis) || !valid_axis(options.vertical_axis) ||
      options.horizontal_axis == options.vertical_axis) {
    throw InputError("odometry plot: axes must be two different components among 0 (x), 1 (y), 2 (z)");
  }
  if (options.png_path.empty()) throw InputError("odometry plot: no output file given");
  const char* names = "xyz";
  std::ostringstream out;
  out << std::setprecision(9);
  write_block(out, "gt", gt, options.horizontal_axis, options.vertical_axis);
  write_block(out, "est", est, options.horizontal_axis, options.vertical_axis);
  out << "$len << EOD\n";
  for (const LengthError& e : per_length)
    out << e.length << ' ' << e.t_rel_pct << ' ' << e.r_rel_deg100m << '\n';
  out << "EOD\n";
  out << "set terminal " << options.terminal << " size 1500,520 noenhanced\n";
  out << "set output " << quoted(options.png_path) << "\n";
  out << "set multiplot layout 1,3 title " << quoted(options.title) << "\n";
  out << "set grid\nset key top left\n";
  out << "set size ratio -1\n";
  out << "set xlabel '" << names[options.horizontal_axis] << " [m]'\n";
  out << "set ylabel '" << names[options.vertical_axis] << " [m]'\n";
  out << "set title 'trajectory (top view)'\n";
  out << "plot $gt using 1:2 with lines lw 2 lc rgb '#d62728' title 'ground truth', \\\n"
         "     $est using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'estimate', \\\n"
         "     $gt every ::0::0 using 1:2 with points pt 4 ps 2 lc rgb 'black' title 'start'\n";
  out << "set size noratio\nset style fill solid 0.6\nset boxwidth 0.6\nset yrange [0:*]\n";
  out << "set xlabel 'segment length [m]'\nunset key\n";
  if (per_length.empty()) {
    out << "set label 1 'no segment: path shorter than every length' at graph 0.5,0.5 center\n";
    out << "unset ylabel\nset title 'translation error [%]'\nplot [0:1] [0:1] NaN\n";
    out << "set title 'rotation error [deg/100 m]'\nplot [0:1] [0:1] NaN\nunset label 1\n";
  } else {
    out << "set xrange [-0.5:" << per_length.size() - 0.5 << "]\n";
    out << "set ylabel 't_rel [%]'\nset title 'translation error per segment length'\n";
    out << "plot $len using 0:2:xtic(1) with boxes lc rgb '#1f77b4'\n";
    out << "set ylabel 'r_rel [deg/100 m]'\nset title 'rotation error per segment length'\n";
    out << "plot $len using 0:3:xtic(1) with boxes lc rgb '#ff7f0e'\n";
  }
  out << "unset multiplot\nset output\n";
  return out.str();
}

}  // namespace dloam::eval
