// `vdbmesh phantom SHAPE -o OUT`: writes a synthetic volume with an exactly known surface
// (include/vdbmesh/phantom.h) in any format vdbmesh reads, slice by slice.
//
// Stored values: density d in 0..1 is stored as d * MAX (--scale MAX; default 255 for u8, 127
// for i8, 1000 for 16- and 32-bit integers, 1 for floats) with value scale 1 / MAX in the
// header, so readers that apply the scale (NIfTI, Analyze, DICOM) see the density and iso 0.5
// is the surface. Formats without a scale field (OpenQVis, MetaImage, NRRD, raw) keep the
// stored numbers: the surface is then at iso 0.5 * MAX, which the command prints.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "commands.h"
#include "common_options.h"
#include "vdbmesh/error.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::cli {

namespace {

constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

struct PhantomOptions {
    std::string shape, output, dims, type = "u8", spacing = "1,1,1", endian = "little", centre, rotate;
    std::int64_t size = 128;
    double blur = 5, noise = 0, scale = 0;
    // Shape lengths: NaN until given (then they override the preset).
    double radius = kUnset, tube_radius = kUnset, side = kUnset, height = kUnset, hole_radius = kUnset;
    std::uint64_t seed = 1;
    bool analyze = false, gzip = false;
    CommonOptions common;
};

std::array<double, 3> three_numbers(const std::string& flag, const std::string& text) {
    const auto values = parse_number_list(flag, text);
    if (values.size() != 3) throw UsageError(flag + ": expected three numbers, got \"" + text + "\"");
    return {values[0], values[1], values[2]};
}

std::array<std::int64_t, 3> parse_dims(const PhantomOptions& o) {
    if (o.dims.empty()) {
        if (o.size < 1) throw UsageError("--size: expected a positive number, got " + std::to_string(o.size));
        return {o.size, o.size, o.size};
    }
    const auto d = three_numbers("--dims", o.dims);
    std::array<std::int64_t, 3> dims{};
    for (int i = 0; i < 3; ++i) {
        if (d[i] < 1 || d[i] != std::floor(d[i]) || d[i] > 9.0e15)
            throw UsageError("--dims: expected positive whole numbers X,Y,Z, got \"" + o.dims + "\"");
        dims[i] = static_cast<std::int64_t>(d[i]);
    }
    return dims;
}

/// The preset for the shape and size, with every length the user gave overriding it.
PhantomSpec make_spec(const PhantomOptions& o) {
    PhantomSpec spec = phantom_preset(o.shape, parse_dims(o));
    auto override_length = [](double given, double& field) {
        if (!std::isnan(given)) field = given;
    };
    override_length(o.radius, spec.radius);
    override_length(o.tube_radius, spec.tube_radius);
    override_length(o.side, spec.side);
    override_length(o.height, spec.height);
    override_length(o.hole_radius, spec.hole_radius);
    if (!o.rotate.empty()) spec.rotation_degrees = three_numbers("--rotate", o.rotate);
    if (!o.centre.empty()) spec.centre = three_numbers("--centre", o.centre);
    spec.blur = o.blur;
    spec.noise_sigma = o.noise;
    spec.seed = o.seed;
    validate_phantom(spec);
    return spec;
}

VolumeHeader make_header(const PhantomOptions& o, const PhantomSpec& spec, double full_scale) {
    VolumeHeader header;
    header.format = o.analyze ? "analyze" : "";
    header.path = o.output;
    header.dims = spec.dims;
    header.type = parse_sample_type(o.type);
    header.byte_order = o.endian == "big" ? ByteOrder::big : ByteOrder::little;
    header.spacing = three_numbers("--spacing", o.spacing);
    for (double s : header.spacing)
        if (!(s > 0)) throw UsageError("--spacing: expected three positive numbers, got \"" + o.spacing + "\"");
    header.index_to_world = axis_aligned_affine(header.spacing);
    header.value_scale = 1.0 / full_scale;
    header.units = "mm";
    return header;
}

void print_summary(const PhantomOptions& o, const PhantomSpec& spec, const VolumeHeader& header,
                   const WriteResult& result, double full_scale) {
    std::ostringstream out;
    out << "wrote " << o.shape << " phantom " << spec.dims[0] << "x" << spec.dims[1] << "x" << spec.dims[2] << " "
        << to_string(header.type) << " (density x " << full_scale << ", blur " << spec.blur << " voxels";
    if (spec.noise_sigma > 0) out << ", noise sigma " << spec.noise_sigma << " seed " << spec.seed;
    out << ")\n";
    for (const auto& file : result.files) out << "  " << file.string() << "\n";
    if (result.value_scale_stored)
        out << "  surface at iso 0.5 (the header's value scale 1/" << full_scale << " gives back the density)\n";
    else
        out << "  surface at iso " << 0.5 * full_scale << " (this format stores no value scale)\n";
    out << "  exact surface area " << phantom_area(spec) << " voxels^2, enclosed volume " << phantom_volume(spec)
        << " voxels^3\n";
    std::cout << out.str();
}

void run_phantom(const PhantomOptions& o) {
    const ThreadLimit threads(o.common);
    const PhantomSpec spec = make_spec(o);
    const SampleType type = parse_sample_type(o.type);
    if (o.scale < 0 || !std::isfinite(o.scale)) throw UsageError("--scale: expected a positive number");
    const double full_scale = o.scale > 0 ? o.scale : phantom_full_scale(type);
    const VolumeHeader header = make_header(o, spec, full_scale);

    Progress progress("phantom", o.common.quiet);
    const SliceSource slices = [&](std::int64_t z, float* slice) {
        fill_phantom_slice(spec, z, slice);
        progress(static_cast<double>(z + 1) / static_cast<double>(spec.dims[2]));
    };
    WriteOptions write_options;
    write_options.gzip = o.gzip;
    const WriteResult result = write_volume(o.output, header, slices, write_options);
    if (!o.common.quiet) print_summary(o, spec, header, result, full_scale);
}

std::string shapes_footer() {
    std::string text = "Shapes: ";
    const auto names = phantom_preset_names();
    for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
    return text +
           ".\nsphere, cube, cylinder and cube-minus-sphere are table 3.1 of the DMC coursework (sizes given for "
           "128^3: radius 40, side 80, height 120, hole radius 50), scaled by min(dims)/128; torus: radius 32, "
           "tube 12; rotated-cube: side 64 turned 30, 20, 10 degrees about x, y, z.\nThe density is "
           "s(d, w) = clamp((w - d) / 2w, 0, 1) of the exact signed distance d (voxels): iso 0.5 is the exact "
           "surface.\nOutputs: .nii .nii.gz .hdr (+.img) .dat .mhd .mha .nrrd .nhdr .raw .raw.gz, or folder/ for a "
           "DICOM series.";
}

}  // namespace

void add_phantom_command(CLI::App& command, CommandResult&) {
    auto options = std::make_shared<PhantomOptions>();
    PhantomOptions& o = *options;
    command.footer(shapes_footer());
    command.add_option("shape", o.shape, "Shape: " + [] {
        std::string names;
        for (const auto& n : phantom_preset_names()) names += (names.empty() ? "" : "|") + n;
        return names;
    }())->required();
    command.add_option("-o,--output", o.output, "Output file (format by extension) or folder/ for DICOM")->required();
    auto* size = command.add_option("--size", o.size, "Cubic volume of N^3 voxels")->capture_default_str();
    command.add_option("--dims", o.dims, "Volume dims X,Y,Z instead of --size")->excludes(size);
    command.add_option("--type", o.type, "Sample type: u8|i8|u16|i16|u32|i32|f32|f64")
        ->check(kSampleTypeName)
        ->capture_default_str();
    command.add_option("--blur", o.blur, "Blur w of s(d, w) in voxels (0: a step)")->check(kFiniteNonNegative)->capture_default_str();
    command.add_option("--noise", o.noise, "Gaussian noise sigma, in density units (0..1)")->check(kFiniteNonNegative)->capture_default_str();
    command.add_option("--seed", o.seed, "Noise seed: the same seed writes the same bytes")->capture_default_str();
    command.add_option("--spacing", o.spacing, "Voxel spacing SX,SY,SZ (mm)")->capture_default_str();
    command.add_option("--scale", o.scale,
                       "Stored value for density 1 (default: u8 255, i8 127, 16/32-bit integers 1000, floats 1)");
    command.add_option("--endian", o.endian, "Byte order of the samples and binary headers")
        ->check(CLI::IsMember({"little", "big"}))
        ->capture_default_str();
    command.add_flag("--analyze", o.analyze, "Write .hdr/.img as Analyze 7.5 (default: a NIfTI pair)");
    command.add_flag("--gzip", o.gzip, "NRRD: gzip encoding (other formats: name the file .nii.gz or .raw.gz)");
    auto* geometry = command.add_option_group("Shape parameters (voxels; default: the preset)");
    geometry->add_option("--radius", o.radius, "Sphere/cylinder radius, torus ring radius")->check(kFinitePositive);
    geometry->add_option("--tube-radius", o.tube_radius, "Torus tube radius")->check(kFinitePositive);
    geometry->add_option("--side", o.side, "Cube edge length")->check(kFinitePositive);
    geometry->add_option("--height", o.height, "Cylinder height")->check(kFinitePositive);
    geometry->add_option("--hole-radius", o.hole_radius, "cube-minus-sphere: radius of the removed ball")->check(kFinitePositive);
    geometry->add_option("--rotate", o.rotate, "Rotation AX,AY,AZ in degrees (about x, then y, then z)");
    geometry->add_option("--centre", o.centre, "Shape centre X,Y,Z in voxel indices (default: the volume centre)");
    add_common_options(command, o.common);
    command.callback([options] { run_phantom(*options); });
}

}  // namespace vdbmesh::cli
