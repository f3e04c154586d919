// SemanticKITTI MOS point confusion, object-level counts (paper eq. 16) and effective features.
#include "dloam/eval/mos_metrics.hpp"

#include <limits>
#include <map>
#include <set>
#include <string>

namespace dloam::eval {
namespace {

using semantic::instance_of;
using semantic::is_ignored;
using semantic::is_moving;

double ratio_or_nan(std::uint64_t num, std::uint64_t den) {
  return den == 0 ? std::numeric_limits<double>::quiet_NaN()
                  : static_cast<double>(num) / static_cast<double>(den);
}

void check_sizes(const std::vector<Label>& gt, const std::vector<Label>& pred) {
  if (gt.size() != pred.size()) {
    throw InputError("MOS evaluation: scan has " + std::to_string(gt.size()) + " ground-truth labels but " +
                     std::to_string(pred.size()) + " predicted labels");
  }
}

struct Hits {
  std::size_t points = 0;
  std::size_t predicted_moving = 0;
};

bool detected(const Hits& hits, double min_fraction) {
  return static_cast<double>(hits.predicted_moving) > min_fraction * static_cast<double>(hits.points);
}

}  // namespace

double MosConfusion::iou() const { return ratio_or_nan(tp, tp + fp + fn); }
double MosConfusion::precision() const { return ratio_or_nan(tp, tp + fp); }
double MosConfusion::recall() const { return ratio_or_nan(tp, tp + fn); }
double MosConfusion::static_iou() const { return ratio_or_nan(tn, tn + fp + fn); }
MosConfusion& MosConfusion::operator+=(const MosConfusion& other) {
  tp += other.tp;
  fp += other.fp;
  fn += other.fn;
  tn += other.tn;
  ignored += other.ignored;
  return *this;
}

double ObjectCounts::iou() const { return ratio_or_nan(tp, tp + fp + fn); }
ObjectCounts& ObjectCounts::operator+=(const ObjectCounts& other) {
  tp += other.tp;
  fp += other.fp;
  fn += other.fn;
  return *this;
}

MosConfusion point_confusion(const std::vector<Label>& gt, const std::vector<Label>& pred) {
  check_sizes(gt, pred);
  MosConfusion c;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (is_ignored(gt[i])) {
      ++c.ignored;
      continue;
    }
    const bool g = is_moving(gt[i]);
    const bool p = is_moving(pred[i]);
    if (g && p) ++c.tp;
    if (!g && p) ++c.fp;
    if (g && !p) ++c.fn;
    if (!g && !p) ++c.tn;
  }
  return c;
}

ObjectCounts object_counts(const std::vector<Label>& gt, const std::vector<Label>& pred,
                           double min_fraction) {
  check_sizes(gt, pred);
  if (!(min_fraction >= 0.0 && min_fraction < 1.0)) {
    throw InputError("MOS evaluation: object threshold " + std::to_string(min_fraction) +
                     " is outside [0, 1)");
  }
  std::map<std::uint32_t, Hits> moving_objects, static_objects;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (is_ignored(gt[i]) || instance_of(gt[i]) == 0) continue;
    Hits& hits = (is_moving(gt[i]) ? moving_objects : static_objects)[instance_of(gt[i])];
    ++hits.points;
    if (is_moving(pred[i])) ++hits.predicted_moving;
  }
  ObjectCounts counts;
  for (const auto& [id, hits] : moving_objects) (detected(hits, min_fraction) ? counts.tp : counts.fn) += 1;
  std::set<std::uint32_t> false_static;  // static GT instances counted as FP in (a)
  for (const auto& [id, hits] : static_objects) {
    if (detected(hits, min_fraction)) false_static.insert(id);
  }
  counts.fp += false_static.size();
  // (b) predicted instances on nothing moving and on no instance already counted in (a).
  std::map<std::uint32_t, bool> predicted_instances;  // id -> touches moving GT or an (a) instance
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (is_ignored(gt[i]) || !is_moving(pred[i]) || instance_of(pred[i]) == 0) continue;
    const bool on_static_fp =
        !is_moving(gt[i]) && instance_of(gt[i]) != 0 && false_static.count(instance_of(gt[i]));
    predicted_instances[instance_of(pred[i])] |= is_moving(gt[i]) || on_static_fp;
  }
  for (const auto& [id, overlaps] : predicted_instances) {
    if (!overlaps) ++counts.fp;
  }
  return counts;
}

void add_scan(MosResult& result, const std::vector<Label>& gt, const std::vector<Label>& pred,
              double min_fraction) {
  result.points += point_confusion(gt, pred);
  result.objects += object_counts(gt, pred, min_fraction);
  ++result.scans;
}

double FeatureCounts::ratio() const { return ratio_or_nan(effective, total); }
FeatureCounts& FeatureCounts::operator+=(const FeatureCounts& other) {
  effective += other.effective;
  total += other.total;
  return *this;
}

FeatureCounts count_effective_features(const std::vector<Label>& gt,
                                       const std::vector<std::size_t>& feature_indices) {
  FeatureCounts counts;
  for (const std::size_t index : feature_indices) {
    if (index >= gt.size()) {
      throw InputError("effective features: feature index " + std::to_string(index) +
                       " is out of range (scan has " + std::to_string(gt.size()) + " points)");
    }
    if (is_ignored(gt[index])) continue;
    ++counts.total;
    if (!is_moving(gt[index])) ++counts.effective;
  }
  return counts;
}

}  // namespace dloam::eval
