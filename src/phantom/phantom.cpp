// Phantoms: the analytic test volumes of the DMC coursework (000_*.txt, section 3.6, table 3.1),
// generated at 128^3 there:
//   sphere of radius 40                 s(sqrt(x^2 + y^2 + z^2) - 40, 5)
//   cube of edge 80                     s(max(|x|, |y|, |z|) - 40, 0)
//   cylinder of radius 40, height 120   s(sqrt(x^2 + y^2) - 40, 5) * s(|z| - 60, 0)
//   cube of edge 80 minus a ball of radius 50
//                                       s(max(|x|, |y|, |z|) - 40, 0) * (1 - s(sqrt(x^2 + y^2 + z^2) - 50, ...))
//                                       (the second factor is garbled in our copy of the text)
// with the blur function (equation 3.1) that "takes the signed distance to the surface and the
// blur coefficient":
//   s(v, w) = 1 if v < -w;  (w - v) / (2w) if -w <= v < w;  0 if v >= w.
// We keep the shapes, their sizes and s(v, w) exactly, but feed s the exact Euclidean signed
// distance of the whole shape (phantom_field.cpp) with one blur w for all of it, so that
// s = 0.5 is exactly the surface (the products above move the 0.5 level near edges, and
// w = 0 leaves no sub-voxel information). Added here: a torus, rotations, and seeded noise.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "phantom_field.h"
#include "vdbmesh/error.h"
#include "vdbmesh/phantom.h"

namespace vdbmesh {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The sizes of table 3.1 are for a 128^3 volume.
constexpr double kTableSize = 128;

/// SplitMix64's finaliser (Steele, Lea and Flood 2014): a bijective 64-bit mixer.
std::uint64_t mix(std::uint64_t h) {
    h += 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    return h ^ (h >> 31);
}

/// A uniform number in (0, 1] from the top 53 bits of @a h.
double unit_interval(std::uint64_t h) { return (static_cast<double>(h >> 11) + 1.0) * 0x1.0p-53; }

/// A standard normal variate depending only on (seed, i, j, k): Box-Muller on two hashed
/// uniforms, so every voxel's noise is independent of the order it is computed in.
double voxel_gaussian(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k) {
    std::uint64_t h = mix(seed);
    for (std::int64_t c : {i, j, k}) h = mix(h ^ static_cast<std::uint64_t>(c));
    const double u1 = unit_interval(h), u2 = unit_interval(mix(h));
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

[[noreturn]] void invalid(const std::string& what) { throw UsageError("phantom: " + what); }

std::string number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

/// Throws UsageError unless @a value is finite and > 0 (>= 0 when @a zero_ok).
void check_length(const char* name, double value, bool zero_ok = false) {
    if (!std::isfinite(value) || value < 0 || (value == 0 && !zero_ok))
        invalid(std::string(name) + " must be " + (zero_ok ? ">= 0" : "positive") + ", got " + number(value));
}

float sample_at(const detail::PhantomField& field, std::int64_t i, std::int64_t j, std::int64_t k) {
    const PhantomSpec& spec = field.spec();
    double value = field.density(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
    if (spec.noise_sigma > 0) value += spec.noise_sigma * voxel_gaussian(spec.seed, i, j, k);
    return static_cast<float>(value);
}

}  // namespace

std::array<double, 3> PhantomSpec::centre_or_default() const {
    if (centre) return *centre;
    return {(dims[0] - 1) / 2.0, (dims[1] - 1) / 2.0, (dims[2] - 1) / 2.0};
}

std::vector<std::string> phantom_preset_names() {
    return {"sphere", "cube", "cylinder", "cube-minus-sphere", "torus", "rotated-cube"};
}

PhantomSpec phantom_preset(const std::string& name, const std::array<std::int64_t, 3>& dims) {
    PhantomSpec spec;
    spec.dims = dims;
    const double f = static_cast<double>(*std::min_element(dims.begin(), dims.end())) / kTableSize;
    spec.radius = 40 * f;
    spec.side = 80 * f;
    spec.height = 120 * f;
    spec.hole_radius = 50 * f;
    spec.tube_radius = 12 * f;
    if (name == "sphere") {
        spec.shape = PhantomShape::sphere;
    } else if (name == "cube") {
        spec.shape = PhantomShape::cube;
    } else if (name == "cylinder") {
        spec.shape = PhantomShape::cylinder;
    } else if (name == "cube-minus-sphere") {
        spec.shape = PhantomShape::cube_minus_sphere;
    } else if (name == "torus") {
        spec.shape = PhantomShape::torus;
        spec.radius = 32 * f;  // the ring plus tube plus blur (32 + 12 + 5) stays inside 128^3
    } else if (name == "rotated-cube") {
        spec.shape = PhantomShape::cube;
        spec.side = 64 * f;  // half diagonal 55.4 plus blur 5 stays inside 128^3 at any angle
        spec.rotation_degrees = {30, 20, 10};
    } else {
        std::string known;
        for (const auto& n : phantom_preset_names()) known += (known.empty() ? "" : ", ") + n;
        throw UsageError("unknown phantom shape \"" + name + "\": expected one of " + known);
    }
    return spec;
}

void validate_phantom(const PhantomSpec& spec) {
    // Called once per phantom_density() call: messages are built only on failure.
    for (std::int64_t d : spec.dims)
        if (d < 1) invalid("dims must be positive, got " + std::to_string(d));
    for (double c : spec.centre_or_default())
        if (!std::isfinite(c)) invalid("the centre must be finite");
    for (double a : spec.rotation_degrees)
        if (!std::isfinite(a)) invalid("rotation angles must be finite");
    check_length("blur", spec.blur, true);
    check_length("noise sigma", spec.noise_sigma, true);
    switch (spec.shape) {
        case PhantomShape::sphere: check_length("radius", spec.radius); break;
        case PhantomShape::cube: check_length("side", spec.side); break;
        case PhantomShape::cylinder:
            check_length("radius", spec.radius);
            check_length("height", spec.height);
            break;
        case PhantomShape::cube_minus_sphere:
            check_length("side", spec.side);
            check_length("hole radius", spec.hole_radius);
            // Beyond side / sqrt(2) the ball cuts the cube's edges and the solid falls apart.
            if (!(spec.hole_radius < spec.side / std::sqrt(2.0)))
                invalid("hole radius must be < side / sqrt(2) = " + number(spec.side / std::sqrt(2.0)) + ", got " +
                        number(spec.hole_radius));
            break;
        case PhantomShape::torus:
            check_length("radius", spec.radius);
            check_length("tube radius", spec.tube_radius);
            if (!(spec.tube_radius < spec.radius))
                invalid("torus tube radius must be < radius, got " + number(spec.tube_radius) + " >= " +
                        number(spec.radius));
            break;
    }
}

double phantom_blur(double v, double w) {
    if (w == 0) return v < 0 ? 1.0 : v > 0 ? 0.0 : 0.5;  // the step; 0.5 on the surface itself
    if (v < -w) return 1.0;
    if (v < w) return (w - v) / (2 * w);
    return 0.0;
}

double phantom_signed_distance(const PhantomSpec& spec, double x, double y, double z) {
    return detail::PhantomField(spec).signed_distance(x, y, z);
}

double phantom_density(const PhantomSpec& spec, double x, double y, double z) {
    return detail::PhantomField(spec).density(x, y, z);
}

float phantom_sample(const PhantomSpec& spec, std::int64_t i, std::int64_t j, std::int64_t k) {
    return sample_at(detail::PhantomField(spec), i, j, k);
}

void fill_phantom_slice(const PhantomSpec& spec, std::int64_t z, float* slice) {
    const detail::PhantomField field(spec);
    const std::int64_t nx = spec.dims[0];
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, spec.dims[1]), [&](const tbb::blocked_range<std::int64_t>& rows) {
        for (std::int64_t y = rows.begin(); y != rows.end(); ++y)
            for (std::int64_t x = 0; x < nx; ++x) slice[y * nx + x] = sample_at(field, x, y, z);
    });
}

double phantom_area(const PhantomSpec& spec) {
    validate_phantom(spec);
    switch (spec.shape) {
        case PhantomShape::sphere: return 4 * kPi * spec.radius * spec.radius;
        case PhantomShape::cube: return 6 * spec.side * spec.side;
        case PhantomShape::cylinder: return 2 * kPi * spec.radius * (spec.radius + spec.height);
        case PhantomShape::torus: return 4 * kPi * kPi * spec.radius * spec.tube_radius;
        case PhantomShape::cube_minus_sphere: {
            const double a = spec.side, h = a / 2, rs = spec.hole_radius;
            if (rs <= h) return 6 * a * a + 4 * kPi * rs * rs;  // a closed cavity
            // Six faces minus a disc of radius^2 rs^2 - h^2 each, plus the sphere minus six caps of height rs - h.
            const double cap_height = rs - h;
            return 6 * (a * a - kPi * (rs * rs - h * h)) + 4 * kPi * rs * rs - 6 * 2 * kPi * rs * cap_height;
        }
    }
    return 0;
}

double phantom_volume(const PhantomSpec& spec) {
    validate_phantom(spec);
    switch (spec.shape) {
        case PhantomShape::sphere: return 4 * kPi * std::pow(spec.radius, 3) / 3;
        case PhantomShape::cube: return std::pow(spec.side, 3);
        case PhantomShape::cylinder: return kPi * spec.radius * spec.radius * spec.height;
        case PhantomShape::torus: return 2 * kPi * kPi * spec.radius * spec.tube_radius * spec.tube_radius;
        case PhantomShape::cube_minus_sphere: {
            const double a = spec.side, h = a / 2, rs = spec.hole_radius;
            double ball_in_cube = 4 * kPi * std::pow(rs, 3) / 3;
            if (rs > h) {  // minus six disjoint caps (rs < h sqrt 2): pi t^2 (3 rs - t) / 3 each
                const double t = rs - h;
                ball_in_cube -= 6 * kPi * t * t * (3 * rs - t) / 3;
            }
            return a * a * a - ball_in_cube;
        }
    }
    return 0;
}

double phantom_full_scale(SampleType type) {
    switch (type) {
        case SampleType::u8: return 255;
        case SampleType::i8: return 127;
        case SampleType::u16:
        case SampleType::i16:
        case SampleType::u32:
        case SampleType::i32: return 1000;
        case SampleType::f32:
        case SampleType::f64: return 1;
    }
    return 1;
}

}  // namespace vdbmesh
