// timing.csv writer (see timing_csv.hpp).
#include "dloam/io/timing_csv.hpp"

#include <cstdio>

#include "dloam/io/atomic_file.hpp"

namespace dloam::io {

void write_timing_csv(const std::string& path, const std::vector<ScanResult>& results) {
  write_atomic(path, [&](std::ostream& out) {
    out << "scan";
    for (auto name : kModuleNames) out << ',' << name << "_ms";
    out << ",edges,planes,mapped,keyframe,loop_closed,degenerate,dt_s,missed_scans,prior_fitness,fitness,"
           "searched,reinitialized,lost,constraint,unconstrained,matches,map_constraint,map_unconstrained,"
           "map_matches,detection_suspended\n";
    char buf[32];
    for (const auto& r : results) {
      out << r.index;
      for (double ms : r.times.ms) {
        std::snprintf(buf, sizeof(buf), "%.3f", ms);
        out << ',' << buf;
      }
      out << ',' << r.n_edges << ',' << r.n_planes << ',' << r.mapped << ',' << r.keyframe << ','
          << r.loop_closed << ',' << r.degenerate;
      std::snprintf(buf, sizeof(buf), "%.6f", r.dt);
      out << ',' << buf << ',' << r.missed_scans;
      std::snprintf(buf, sizeof(buf), "%.3f,%.3f", r.prior_fitness, r.fitness);
      out << ',' << buf << ',' << (r.search_candidates > 0) << ',' << r.reinitialized << ',' << r.lost;
      // Degeneracy: the smallest eigenvalue (features' worth), the axes of the unconstrained
      // directions, the matched features; empty where nothing was registered.
      for (const Degeneracy* d : {&r.degeneracy, &r.map_degeneracy}) {
        if (d->free == 0) {
          out << ",,,";
          continue;
        }
        std::snprintf(buf, sizeof(buf), "%.1f", d->weakest());
        out << ',' << buf << ',' << unconstrained_names(*d) << ',' << d->matches;
      }
      out << ',' << r.detection_suspended << '\n';
    }
  });
}

}  // namespace dloam::io
