// A binary mask (one AAL label written as 0/1) meshes smooth, not as Lego: at most 5% of its
// triangles' normals more than 30 degrees from the outward normal of the mask's Gaussian-smoothed
// field (the figure), where the voxel faces themselves (no smoothing) fail it.

#include <gtest/gtest.h>

#include <cmath>

#include "test_data.h"
#include "vdbmesh/labels.h"
#include "vdbmesh/read.h"

namespace vdbmesh {
namespace {

/// The Gaussian's width in voxels: wide enough to round off one-voxel steps, narrow against the
/// structure (the gyri are 5-10 voxels across); the kernel is cut at 3 sigma.
constexpr double kSigma = 1.5;
constexpr double kMaxAngleDegrees = 30;
constexpr double kMaxShare = 0.05;

/// A dense float field over dims (x fastest).
struct Field {
    std::array<std::int64_t, 3> dims;
    std::vector<float> values;
    float at(std::int64_t x, std::int64_t y, std::int64_t z) const {
        x = std::clamp<std::int64_t>(x, 0, dims[0] - 1), y = std::clamp<std::int64_t>(y, 0, dims[1] - 1),
        z = std::clamp<std::int64_t>(z, 0, dims[2] - 1);
        return values[std::size_t((z * dims[1] + y) * dims[0] + x)];
    }
    double trilinear(const std::array<double, 3>& p) const {
        const std::int64_t x = std::int64_t(std::floor(p[0])), y = std::int64_t(std::floor(p[1])), z = std::int64_t(std::floor(p[2]));
        const double fx = p[0] - x, fy = p[1] - y, fz = p[2] - z;
        double sum = 0;
        for (int c = 0; c < 8; ++c)
            sum += (c & 1 ? fx : 1 - fx) * (c & 2 ? fy : 1 - fy) * (c & 4 ? fz : 1 - fz) * at(x + (c & 1), y + (c >> 1 & 1), z + (c >> 2 & 1));
        return sum;
    }
};

Field gaussian(const LabelVolume& mask) {
    Field f{mask.header.dims, {}};
    for (std::uint16_t l : mask.labels) f.values.push_back(float(l));
    const int radius = int(std::ceil(3 * kSigma));
    std::vector<double> kernel;
    double total = 0;
    for (int i = -radius; i <= radius; ++i) kernel.push_back(std::exp(-0.5 * i * i / (kSigma * kSigma))), total += kernel.back();
    for (double& k : kernel) k /= total;
    for (int axis = 0; axis < 3; ++axis) {
        Field next = f;
        for (std::int64_t z = 0; z < f.dims[2]; ++z)
            for (std::int64_t y = 0; y < f.dims[1]; ++y)
                for (std::int64_t x = 0; x < f.dims[0]; ++x) {
                    double sum = 0;
                    for (int i = -radius; i <= radius; ++i) {
                        std::array<std::int64_t, 3> p{x, y, z};
                        p[axis] += i;
                        sum += kernel[std::size_t(i + radius)] * f.at(p[0], p[1], p[2]);
                    }
                    next.values[std::size_t((z * f.dims[1] + y) * f.dims[0] + x)] = float(sum);
                }
        f = std::move(next);
    }
    return f;
}

/// Share of triangles whose normal is more than kMaxAngleDegrees from the field's outward normal
/// (minus its gradient) at the triangle's centroid. The mesh is in index coordinates.
double share_off_field(const Mesh& mesh, const Field& field) {
    std::size_t off = 0;
    for (const auto& t : mesh.triangles) {
        std::array<double, 3> a, b, c, centroid, gradient;
        for (int k = 0; k < 3; ++k) {
            a[k] = mesh.vertices[t[0]][k], b[k] = mesh.vertices[t[1]][k], c[k] = mesh.vertices[t[2]][k];
            centroid[k] = (a[k] + b[k] + c[k]) / 3;
        }
        for (int k = 0; k < 3; ++k) {
            std::array<double, 3> plus = centroid, minus = centroid;
            plus[k] += 0.5, minus[k] -= 0.5;
            gradient[k] = field.trilinear(plus) - field.trilinear(minus);
        }
        const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        const double dot = -(n[0] * gradient[0] + n[1] * gradient[1] + n[2] * gradient[2]);
        const double norms = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) *
                             std::sqrt(gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
        if (!(dot > norms * std::cos(kMaxAngleDegrees * M_PI / 180))) ++off;
    }
    return double(off) / double(mesh.triangles.size());
}

/// AAL's label @a value as a 0/1 mask over its bounding box and a margin, identity transform.
LabelVolume aal_mask(const std::filesystem::path& path, std::uint16_t value) {
    auto reader = open_volume(path);
    const LabelVolume aal = read_label_volume(*reader);
    std::array<std::int64_t, 3> lo{aal.header.dims}, hi{0, 0, 0};
    for (std::int64_t z = 0; z < aal.header.dims[2]; ++z)
        for (std::int64_t y = 0; y < aal.header.dims[1]; ++y)
            for (std::int64_t x = 0; x < aal.header.dims[0]; ++x)
                if (aal.at(x, y, z) == value) {
                    const std::array<std::int64_t, 3> p{x, y, z};
                    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
                }
    const std::int64_t margin = 6;
    LabelVolume mask;
    mask.header.path = path;
    for (int k = 0; k < 3; ++k) mask.header.dims[k] = hi[k] - lo[k] + 1 + 2 * margin;
    for (std::int64_t z = 0; z < mask.header.dims[2]; ++z)
        for (std::int64_t y = 0; y < mask.header.dims[1]; ++y)
            for (std::int64_t x = 0; x < mask.header.dims[0]; ++x) {
                const std::int64_t ax = x + lo[0] - margin, ay = y + lo[1] - margin, az = z + lo[2] - margin;
                const bool inside = ax >= 0 && ay >= 0 && az >= 0 && ax < aal.header.dims[0] && ay < aal.header.dims[1] &&
                                    az < aal.header.dims[2] && aal.at(ax, ay, az) == value;
                mask.labels.push_back(inside ? 1 : 0);
            }
    return mask;
}

TEST(LabelSmoothnessTest, ABinaryMaskMeshesSmoothWhereVoxelFacesDoNot) {
    VDBMESH_SHARED_DATA(path, "nifti_mricron_label_atlases/aal.nii.gz");
    for (const std::uint16_t value : {37, 1}) {  // Hippocampus_L, Precentral_L
        const LabelVolume mask = aal_mask(path, value);
        const Field field = gaussian(mask);
        const double smooth = share_off_field(label_mesh(mesh_labels(mask), 1), field);
        LabelMeshOptions lego;
        lego.smoothing_iterations = 0;
        const double voxel_faces = share_off_field(label_mesh(mesh_labels(mask, lego), 1), field);
        EXPECT_LE(smooth, kMaxShare) << "label " << value;
        EXPECT_GT(voxel_faces, kMaxShare) << "label " << value << ": the test would not tell Lego apart";
        RecordProperty("share_off_" + std::to_string(value), std::to_string(smooth));
        std::cout << "label " << value << ": " << 100 * smooth << "% of normals off by > 30 degrees (voxel faces: "
                  << 100 * voxel_faces << "%)\n";
    }
}

}  // namespace
}  // namespace vdbmesh
