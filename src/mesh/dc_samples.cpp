// A block's samples for intersection-free contouring: the window of samples round it read
// from the grid (load_ifc_samples()), its corner signs (IfcSamples), and the Hermite data of its
// crossed edges (edge_hermite()), which the block's octree (dc_octree.cpp) tests and places
// vertices with.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "mesh/dc_block.h"

namespace vdbmesh::detail {

unsigned IfcSamples::config(int x, int y, int z) const {
    // Corner c at (c & 1, (c >> 1) & 1, c >> 2), as an offset from the cell's minimum sample.
    const unsigned rows[4] = {row(x, y), row(x + 1, y), row(x, y + 1), row(x + 1, y + 1)};
    unsigned config = 0;
    for (unsigned c = 0; c < 8; ++c) config |= ((rows[c & 3] >> (z + 1 + (c >> 2))) & 1u) << c;
    return config;
}

bool IfcSamples::uniform() const {
    const std::uint16_t first = inside_rows[0];
    if (first != 0 && first != 0x7ff) return false;
    return std::all_of(inside_rows.begin(), inside_rows.end(), [&](std::uint16_t r) { return r == first; });
}

namespace {

/// Copies a row of 1, 2 or 8 floats; the fixed sizes are inlined (a call to memmove per
/// short row cost as much as the copy).
void copy_row(const float* source, int length, float* row) {
    switch (length) {
        case 8: std::memcpy(row, source, 8 * sizeof(float)); break;
        case 2: std::memcpy(row, source, 2 * sizeof(float)); break;
        case 1: *row = *source; break;
        default: std::memcpy(row, source, std::size_t(length) * sizeof(float));
    }
}

}  // namespace

void load_ifc_samples(openvdb::FloatGrid::ConstAccessor& accessor, const SampleClassifier& classifier, IfcSamples& samples) {
    // The window spans up to 27 leaves: each is read from its buffer a row along z at a time,
    // or where there is no leaf, as the one value of its tile (or the background); both as
    // getValue() would.
    static constexpr int kSpanMin[3] = {-1, 0, kIfcBlock}, kSpanMax[3] = {0, kIfcBlock, kIfcSampleDim - 1};
    using Leaf = openvdb::FloatTree::LeafNodeType;
    for (int rx = 0; rx < 3; ++rx) {
        for (int ry = 0; ry < 3; ++ry) {
            for (int rz = 0; rz < 3; ++rz) {
                const openvdb::Coord corner = samples.origin.offsetBy(kSpanMin[rx], kSpanMin[ry], kSpanMin[rz]);
                const Leaf* leaf = accessor.probeConstLeaf(corner);
                const float tile = leaf ? 0.0f : accessor.getValue(corner);
                const openvdb::Coord local = corner - (corner & ~(Leaf::DIM - 1));
                const int row_length = kSpanMax[rz] - kSpanMin[rz];
                for (int x = kSpanMin[rx]; x < kSpanMax[rx]; ++x) {
                    for (int y = kSpanMin[ry]; y < kSpanMax[ry]; ++y) {
                        float* row = &samples.value[IfcSamples::index(x, y, kSpanMin[rz])];
                        if (!leaf) {
                            std::fill(row, row + row_length, tile);
                            continue;
                        }
                        const float* source = leaf->buffer().data() + Leaf::coordToOffset(local.offsetBy(x - kSpanMin[rx], y - kSpanMin[ry], 0));
                        copy_row(source, row_length, row);
                    }
                }
            }
        }
    }
    samples.scan_box = classifier.scan_box() ? &*classifier.scan_box() : nullptr;
    samples.source = {&accessor, &classifier};
    const openvdb::CoordBBox window(samples.origin.offsetBy(-1), samples.origin.offsetBy(kIfcSampleDim - 2));
    if (samples.scan_box && !samples.scan_box->isInside(window)) {
        // Samples beyond the scanned box take its outside value: whole rows where x or y is
        // beyond it, else the ends of the row beyond it along z.
        const openvdb::CoordBBox& box = *classifier.scan_box();
        const float outside = float(classifier.sample_value(box.max().offsetBy(1), 0.0f));
        const openvdb::Coord& o = samples.origin;
        for (int x = -1; x < kIfcSampleDim - 1; ++x) {
            for (int y = -1; y < kIfcSampleDim - 1; ++y) {
                float* row = &samples.value[IfcSamples::index(x, y, -1)];
                const bool row_in_box = o.x() + x >= box.min().x() && o.x() + x <= box.max().x() && o.y() + y >= box.min().y() &&
                                        o.y() + y <= box.max().y();
                for (int z = -1; z < kIfcSampleDim - 1; ++z) {
                    if (!row_in_box || o.z() + z < box.min().z() || o.z() + z > box.max().z()) row[z + 1] = outside;
                }
            }
        }
    }
    for (std::size_t r = 0; r < samples.inside_rows.size(); ++r) {
        samples.inside_rows[r] = std::uint16_t(classifier.inside_bits(&samples.value[r * kIfcSampleDim], kIfcSampleDim));
    }
}

namespace {

/// Central-difference gradient at local sample (x, y, z) of the block's own samples (0..8,
/// so both neighbours are in the window); zero where a difference is not finite (beyond the
/// scan box).
Point3d gradient(const IfcSamples& s, int x, int y, int z) {
    static constexpr int kStride[3] = {kIfcSampleDim * kIfcSampleDim, kIfcSampleDim, 1};
    const int i = IfcSamples::index(x, y, z);
    Point3d g;
    for (int a = 0; a < 3; ++a) {
        const double d = (double(s.value[i + kStride[a]]) - double(s.value[i - kStride[a]])) * 0.5;
        g[a] = std::isfinite(d) ? d : 0.0;
    }
    return g;
}

}  // namespace

Hermite edge_hermite(const IfcSamples& s, double iso, int x, int y, int z, int axis) {
    const int x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
    const Point3d p0 = {double(s.origin.x() + x), double(s.origin.y() + y), double(s.origin.z() + z)};
    Point3d p1 = p0;
    p1[axis] += 1.0;
    Hermite h;
    h.point = edge_crossing(p0, s.at(x, y, z), p1, s.at(x1, y1, z1), iso);
    const double t = h.point[axis] - p0[axis];
    const Point3d g0 = gradient(s, x, y, z), g1 = gradient(s, x1, y1, z1);
    double length = 0;
    for (int a = 0; a < 3; ++a) {
        h.normal[a] = (1 - t) * g0[a] + t * g1[a];
        length += h.normal[a] * h.normal[a];
    }
    length = std::sqrt(length);
    if (!(length > 0) || !std::isfinite(length)) {
        // Beyond the scan box, or a flat spot: the surface is taken across the edge.
        h.normal = {0, 0, 0};
        h.normal[axis] = 1;
    } else {
        for (double& n : h.normal) n /= length;
    }
    return h;
}

}  // namespace vdbmesh::detail
