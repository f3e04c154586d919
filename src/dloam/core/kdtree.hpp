// k-d tree over a vector of 3D points (nanoflann), for nearest-feature search.
#pragma once

#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

class KdTree {
 public:
  KdTree() = default;
  explicit KdTree(std::vector<Vec3> points) { build(std::move(points)); }
  // The index refers to the stored points: the tree is neither copied nor moved.
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;

  void build(std::vector<Vec3> points) {
    adaptor_.pts = std::move(points);
    index_ = std::make_unique<Index>(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  }
  [[nodiscard]] const std::vector<Vec3>& points() const { return adaptor_.pts; }
  [[nodiscard]] std::size_t size() const { return adaptor_.pts.size(); }

  /// The k nearest points: indices and squared distances, nearest first. Returns how many were found.
  std::size_t knn(const Vec3& q, std::size_t k, std::uint32_t* indices, double* sq_dists) const {
    if (!index_ || adaptor_.pts.empty()) return 0;
    return index_->knnSearch(q.data(), k, indices, sq_dists);
  }

 private:
  struct Adaptor {
    std::vector<Vec3> pts;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts.size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t d) const {
      return pts[i][static_cast<int>(d)];
    }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
      return false;
    }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3,
                                                    std::uint32_t>;
  Adaptor adaptor_;
  std::unique_ptr<Index> index_;
};

}  // namespace dloam
