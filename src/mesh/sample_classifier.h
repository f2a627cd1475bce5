#pragma once
// Private: which samples of a grid are inside the object, by the rule of edge_crossing.h: a
// sample is inside when it lies in the scanned box (kMetaScanMin/Max metadata, when present)
// and its value is strictly on the inside side of the isovalue.

#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#ifdef __SSE__
#include <xmmintrin.h>
#endif

#include "mesh/edge_crossing.h"
#include "vdbmesh/mesher.h"

namespace vdbmesh::detail {

class SampleClassifier {
public:
    SampleClassifier(const openvdb::FloatGrid& grid, const MeshOptions& options);

    /// The scanned box (index space, inclusive), if the grid records one.
    const std::optional<openvdb::CoordBBox>& scan_box() const { return box_; }
    bool in_box(const openvdb::Coord& ijk) const { return !box_ || box_->isInside(ijk); }
    /// Whether a value (finite, or outside_scan_value()) is inside the object.
    bool inside(double value) const { return is_inside_value(value, iso_, above_); }
    /// Bit i set for each of the @a count (at most 32) values that is inside, as inside() says.
    std::uint32_t inside_bits(const float* values, int count) const {
        // Compared as floats with the nearest float beyond the isovalue (the same answers as in
        // double), four at a time where SSE is there (every x86-64): the octree classifies
        // 121 rows of 11 samples per block. A NaN is outside either way.
        std::uint32_t bits = 0;
        int i = 0;
#ifdef __SSE__
        const __m128 threshold = _mm_set1_ps(first_inside_);
        for (; i + 4 <= count; i += 4) {
            const __m128 v = _mm_loadu_ps(values + i);
            bits |= std::uint32_t(_mm_movemask_ps(above_ ? _mm_cmpge_ps(v, threshold) : _mm_cmple_ps(v, threshold))) << i;
        }
#endif
        for (; i < count; ++i) bits |= std::uint32_t(above_ ? values[i] >= first_inside_ : values[i] <= first_inside_) << i;
        return bits;
    }
    /// The value meshers use for the sample at @a ijk holding @a value: itself inside the box,
    /// outside_scan_value() beyond it.
    double sample_value(const openvdb::Coord& ijk, float value) const {
        return in_box(ijk) ? double(value) : outside_scan_value(above_);
    }
    /// With open_boundary: whether the cell whose minimum corner is @a ijk lies in the box.
    bool cell_in_box(const openvdb::Coord& ijk) const {
        return !box_ || (box_->isInside(ijk) && box_->isInside(ijk.offsetBy(1)));
    }
    double iso() const { return iso_; }

private:
    double iso_;
    bool above_;
    /// The float nearest the isovalue on the inside side (strictly beyond it): a float is
    /// inside iff it is this one or beyond.
    float first_inside_;
    std::optional<openvdb::CoordBBox> box_;
};

}  // namespace vdbmesh::detail
