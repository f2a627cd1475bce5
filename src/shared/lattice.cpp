// Lattice fields for the shared tree: gyroid, Schwarz P, diamond (sheet or solid) and a
// body-centred strut lattice, as narrow-band level sets cut by a box and optionally a clip solid.
//
// TPMS distances: the implicit function g (phases u = 2 pi x / period) divided by the length of
// its world-space gradient, a first-order distance that is exact on the surface g = 0. A sheet
// of thickness t is |g / |grad g|| - t / 2; a solid at level c is (g - c) / |grad g|.
// Struts: distance to the 4 body diagonals of each cell (and, by folding, of the neighbours'
// cells through the corners), minus the radius.

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vdbmesh/error.h"
#include "vdbmesh/lattice.h"

namespace vdbmesh {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

std::string str(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

double segment_distance(const std::array<double, 3>& p, const std::array<double, 3>& a, const std::array<double, 3>& b) {
    double ab[3], ap[3];
    double ab2 = 0, t = 0;
    for (int i = 0; i < 3; ++i) {
        ab[i] = b[i] - a[i];
        ap[i] = p[i] - a[i];
        ab2 += ab[i] * ab[i];
        t += ap[i] * ab[i];
    }
    t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double d = ap[i] - t * ab[i];
        d2 += d * d;
    }
    return std::sqrt(d2);
}

/// The lattice value (world units) from the sines and cosines of the phases u = 2 pi x / period
/// (sin u, cos u, sin v, cos v, sin w, cos w) and the positions q (world units within the cell).
double lattice_from(const LatticeOptions& o, const double sc[6], const double q[3]) {
    if (o.kind == LatticeKind::bcc_struts) {
        const double h = o.period / 2;
        // Fold into the octant of the cell centre towards the corner (h, h, h).
        const std::array<double, 3> a = {std::abs(q[0] - h), std::abs(q[1] - h), std::abs(q[2] - h)};
        double d = segment_distance(a, {0, 0, 0}, {h, h, h});
        for (int s = 0; s < 7; ++s) {  // the neighbours' struts through the corner, leaving it outward
            const std::array<double, 3> end = {h + ((s & 1) ? h : -h), h + ((s & 2) ? h : -h), h + ((s & 4) ? h : -h)};
            d = std::min(d, segment_distance(a, {h, h, h}, end));
        }
        return d - *o.thickness / 2;
    }
    const double su = sc[0], cu = sc[1], sv = sc[2], cv = sc[3], sw = sc[4], cw = sc[5];
    double g = 0, gx = 0, gy = 0, gz = 0;
    switch (o.kind) {
        case LatticeKind::gyroid:
            g = su * cv + sv * cw + sw * cu;
            gx = cu * cv - sw * su;
            gy = -su * sv + cv * cw;
            gz = -sv * sw + cw * cu;
            break;
        case LatticeKind::schwarz_p:
            g = cu + cv + cw;
            gx = -su;
            gy = -sv;
            gz = -sw;
            break;
        case LatticeKind::diamond:
            g = su * sv * sw + su * cv * cw + cu * sv * cw + cu * cv * sw;
            gx = cu * sv * sw + cu * cv * cw - su * sv * cw - su * cv * sw;
            gy = su * cv * sw - su * sv * cw + cu * cv * cw - cu * sv * sw;
            gz = su * sv * cw - su * cv * sw - cu * sv * sw + cu * cv * cw;
            break;
        case LatticeKind::bcc_struts:
            break;
    }
    const double grad = std::max(std::sqrt(gx * gx + gy * gy + gz * gz) * kTwoPi / o.period, 1e-12);
    if (o.thickness) return std::abs(g / grad) - *o.thickness / 2;
    return (g - *o.level) / grad;
}

using Internal1 = openvdb::FloatTree::RootNodeType::ChildNodeType::ChildNodeType;
using Internal2 = openvdb::FloatTree::RootNodeType::ChildNodeType;

class LatticeField final : public LeafField {
public:
    LatticeField(const LatticeOptions& o, const openvdb::FloatGrid* clip) : o_(o), clip_(clip) {
        h_ = o.voxel;
        bg_ = float(o.band * o.voxel);
        const double p = o.period / o.voxel;
        periodic_ = std::abs(p - std::round(p)) < 1e-9 * std::max(1.0, p) && std::round(p) >= 1;
        P_ = periodic_ ? long(std::round(p)) : 0;
        for (int a = 0; a < 3; ++a) {
            lo_[a] = int(std::floor(o.box_min[a] / h_)) - int(std::ceil(o.band)) - 1;
            hi_[a] = int(std::ceil((o.box_min[a] + o.box[a]) / h_)) + int(std::ceil(o.band)) + 1;
        }
        if (clip_) {
            const double cv = clip_->voxelSize()[0];
            if (std::abs(cv - h_) > 1e-9 * h_ || clip_->transform().indexToWorld(openvdb::Vec3d(0)).length() != 0.0 ||
                !clip_->transform().hasUniformScale()) {
                throw UsageError("--clip: expected a level set with voxel size " + str(h_) + " and no translation, got voxel size " + str(cv));
            }
            if (clip_->background() < bg_) {
                throw UsageError("--clip: expected a narrow band of at least " + str(bg_) + ", got " + str(clip_->background()));
            }
        }
    }
    float background() const override { return bg_; }
    double voxel_size() const override { return h_; }
    std::array<Coord3, 2> bounds() const override { return {lo_, hi_}; }

    double box_value(long i, long j, long k) const {
        const long idx[3] = {i, j, k};
        double d = -std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            const double x = double(idx[a]) * h_;
            d = std::max(d, std::max(o_.box_min[a] - x, x - (o_.box_min[a] + o_.box[a])));
        }
        return d;
    }

    /// Per axis, for the 8 samples of a leaf: the phase's sine and cosine and the position in the cell.
    struct AxisSamples {
        double s[8], c[8], q[8];
    };
    AxisSamples axis_samples(long first) const {
        AxisSamples a;
        for (int k = 0; k < 8; ++k) {
            double u;
            const long i = first + k;
            if (periodic_) {
                const long r = ((i % P_) + P_) % P_;
                u = kTwoPi * (double(r) / double(P_));
                a.q[k] = double(r) * h_;
            } else {
                const double x = double(i) * h_;
                u = kTwoPi * x / o_.period;
                a.q[k] = x - std::floor(x / o_.period) * o_.period;
            }
            a.s[k] = std::sin(u);
            a.c[k] = std::cos(u);
        }
        return a;
    }

    void evaluate(const Coord3& origin, SharedLeaf& leaf) const override {
        std::optional<openvdb::FloatGrid::ConstAccessor> clip;
        if (clip_) clip.emplace(clip_->getConstAccessor());
        const AxisSamples ax = axis_samples(origin[0]), ay = axis_samples(origin[1]), az = axis_samples(origin[2]);
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const long i = origin[0] + x, j = origin[1] + y, k = origin[2] + z;
                    const double sc[6] = {ax.s[x], ax.c[x], ay.s[y], ay.c[y], az.s[z], az.c[z]};
                    const double q[3] = {ax.q[x], ay.q[y], az.q[z]};
                    double v = std::max(lattice_from(o_, sc, q), box_value(i, j, k));
                    if (clip) v = std::max(v, double(clip->getValue(openvdb::Coord(int(i), int(j), int(k)))));
                    const int n = (x * 8 + y) * 8 + z;
                    float f = float(v);
                    const bool active = f > -bg_ && f < bg_;
                    if (!active) f = f > 0 ? bg_ : -bg_;
                    leaf.values[n] = f;
                    leaf.set_active(n, active);
                }
    }

    /// Whether every voxel of the region is at least @a margin inside the box along @a axis.
    bool deep_along(const Coord3& o, int dim, double margin, int a) const {
        return double(o[a]) * h_ - o_.box_min[a] >= margin && o_.box_min[a] + o_.box[a] - double(o[a] + dim - 1) * h_ >= margin;
    }

    /// The clip's value over the region when it is one tile (no node below @a dim there).
    bool clip_tile(const Coord3& origin, int dim, float& value) const {
        const openvdb::Coord o(origin[0], origin[1], origin[2]);
        const auto& tree = clip_->tree();
        bool uniform;
        if (dim == 8) uniform = tree.probeConstLeaf(o) == nullptr;
        else if (dim == 128) uniform = tree.probeConstNode<Internal1>(o) == nullptr;
        else uniform = tree.probeConstNode<Internal2>(o) == nullptr;
        if (uniform) value = tree.getValue(o);
        return uniform;
    }

    bool uniform_region(const Coord3& o, int dim, SharedTile& tile) const override {
        for (int a = 0; a < 3; ++a) {
            const double far = bg_ + h_;
            if (double(o[a] + dim - 1) * h_ < o_.box_min[a] - far || double(o[a]) * h_ > o_.box_min[a] + o_.box[a] + far) {
                tile = {bg_, false};
                return true;
            }
        }
        float v;
        if (clip_ && clip_tile(o, dim, v) && v >= bg_) {
            tile = {bg_, false};
            return true;
        }
        return false;
    }

    unsigned periodic_key(const Coord3& o, int dim, Coord3& key) const override {
        // Along an axis where the region is deep inside the box, the box never decides a value
        // (clamped), so the values repeat with the period along it. A clip must be one inside
        // tile over the region (then it never decides either).
        if (!periodic_) return 0;
        float v;
        if (clip_ && !(clip_tile(o, dim, v) && v <= -bg_)) return 0;
        unsigned axes = 0;
        for (int a = 0; a < 3; ++a) {
            if (deep_along(o, dim, bg_ + h_, a)) {
                axes |= 1u << a;
                key[a] = int(((long(o[a]) % P_) + P_) % P_);
            } else {
                key[a] = o[a];
            }
        }
        return axes;
    }

private:
    LatticeOptions o_;
    const openvdb::FloatGrid* clip_;
    double h_;
    float bg_;
    bool periodic_;
    long P_;
    Coord3 lo_, hi_;
};

}  // namespace

LatticeKind parse_lattice_kind(const std::string& name) {
    if (name == "gyroid") return LatticeKind::gyroid;
    if (name == "schwarz-p" || name == "schwarzp" || name == "primitive") return LatticeKind::schwarz_p;
    if (name == "diamond") return LatticeKind::diamond;
    if (name == "bcc" || name == "bcc-struts") return LatticeKind::bcc_struts;
    throw UsageError("lattice: expected gyroid, schwarz-p, diamond or bcc, got \"" + name + "\"");
}

void check_lattice_options(const LatticeOptions& o) {
    auto positive = [](const char* flag, double v) {
        if (!(v > 0) || !std::isfinite(v)) throw UsageError(std::string(flag) + ": expected a positive number, got " + str(v));
    };
    positive("--period", o.period);
    positive("--voxel", o.voxel);
    for (double b : o.box) positive("--box", b);
    if (!(o.band >= 1) || !std::isfinite(o.band)) throw UsageError("--band: expected at least 1 voxel, got " + str(o.band));
    if (o.kind == LatticeKind::bcc_struts) {
        if (!o.thickness) throw UsageError("--thickness: expected the strut diameter for bcc, got none");
        if (o.level) throw UsageError("--level: bcc is a strut lattice (use --thickness), got --level " + str(*o.level));
    } else if (o.thickness.has_value() == o.level.has_value()) {
        throw UsageError("lattice: expected exactly one of --thickness (sheet) and --level (solid)");
    }
    if (o.thickness) positive("--thickness", *o.thickness);
    if (o.thickness && *o.thickness >= o.period) {
        throw UsageError("--thickness: expected less than the period " + str(o.period) + ", got " + str(*o.thickness));
    }
    if (o.level && !std::isfinite(*o.level)) throw UsageError("--level: expected a finite number");
    for (double b : o.box_min) {
        if (!std::isfinite(b)) throw UsageError("--box: expected a finite corner");
    }
    for (double b : o.box) {
        const double n = b / o.voxel;
        if (n > 1 << 20) throw UsageError("--box / --voxel: expected at most 2^20 voxels per axis, got " + str(n));
        if (n < 1) throw UsageError("--voxel: expected at most the --box side " + str(b) + ", got " + str(o.voxel));
    }
}

std::unique_ptr<LeafField> make_lattice_field(const LatticeOptions& options, const openvdb::FloatGrid* clip) {
    check_lattice_options(options);
    return std::make_unique<LatticeField>(options, clip);
}

double lattice_value(const LatticeOptions& options, const std::array<double, 3>& p) {
    double sc[6], q[3];
    for (int a = 0; a < 3; ++a) {
        const double u = kTwoPi * p[a] / options.period;
        sc[2 * a] = std::sin(u);
        sc[2 * a + 1] = std::cos(u);
        q[a] = p[a] - std::floor(p[a] / options.period) * options.period;
    }
    return lattice_from(options, sc, q);
}

}  // namespace vdbmesh
