#pragma once
// The k-d tree of the points stage (nanoflann, private): nearest neighbours of 3-D points.

#include <nanoflann.hpp>

#include <vector>

#include "vdbmesh/points.h"

namespace vdbmesh::points_detail {

class KdTree {
public:
    explicit KdTree(const std::vector<Vec3d>& points)
        : adaptor_{&points}, index_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
        index_.buildIndex();
    }
    /// The k nearest points of @a q (fewer when the cloud is smaller), nearest first.
    void knn(const Vec3d& q, std::size_t k, std::vector<std::size_t>& index, std::vector<double>& dist2) const {
        k = std::min(k, adaptor_.points->size());
        index.resize(k);
        dist2.resize(k);
        const std::size_t found = index_.knnSearch(q.data(), k, index.data(), dist2.data());
        index.resize(found);
        dist2.resize(found);
    }
    /// The indices of the points within @a radius of @a q (in no particular order).
    void within(const Vec3d& q, double radius, std::vector<std::size_t>& index) const {
        std::vector<std::pair<std::size_t, double>> found;
        index_.radiusSearch(q.data(), radius * radius, found, nanoflann::SearchParams(32, 0.0f, false));
        index.resize(found.size());
        for (std::size_t i = 0; i < found.size(); ++i) index[i] = found[i].first;
    }
    /// Index of the nearest point.
    std::size_t nearest(const Vec3d& q, double* dist2 = nullptr) const {
        std::size_t i = 0;
        double d = 0;
        index_.knnSearch(q.data(), 1, &i, &d);
        if (dist2) *dist2 = d;
        return i;
    }

private:
    struct Adaptor {
        const std::vector<Vec3d>* points;
        std::size_t kdtree_get_point_count() const { return points->size(); }
        double kdtree_get_pt(std::size_t i, std::size_t d) const { return (*points)[i][d]; }
        template <class Box>
        bool kdtree_get_bbox(Box&) const { return false; }
    };
    using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3, std::size_t>;
    Adaptor adaptor_;
    Index index_;
};

}  // namespace vdbmesh::points_detail
