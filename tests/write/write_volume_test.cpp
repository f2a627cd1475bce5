// The volume writers (write_volume and src/write/write_*.cpp): every format read back
// through open_volume, the binary header fields that a reader could get wrong the same way,
// atomic failure, determinism, and the `vdbmesh phantom` command.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "binary_test_util.h"
#include "cli.h"
#include "test_data.h"
#include "vdbmesh/error.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh {
namespace {

using test::Bytes;

/// A small noisy sphere with odd dims (axis mix-ups show) whose noise reaches beyond 0..1,
/// so that clamping to the sample type is exercised too.
PhantomSpec small_phantom() {
    PhantomSpec spec;
    spec.dims = {13, 11, 7};
    spec.radius = 4.5;
    spec.blur = 2;
    spec.noise_sigma = 0.08;
    spec.seed = 3;
    return spec;
}

SliceSource slices_of(const PhantomSpec& spec) {
    return [spec](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); };
}

VolumeHeader header_for(SampleType type, ByteOrder order, const std::array<double, 3>& origin) {
    VolumeHeader header;
    header.dims = small_phantom().dims;
    header.type = type;
    header.byte_order = order;
    header.spacing = {0.5, 0.75, 1.25};
    header.index_to_world = axis_aligned_affine(header.spacing, origin);
    header.value_scale = 1.0 / phantom_full_scale(type);
    header.units = "mm";
    return header;
}

/// What a sample of value @a v is stored as (the contract of write_volume), as a double.
double stored_value(float v, const VolumeHeader& header) {
    const double x = (static_cast<double>(v) - header.value_offset) / header.value_scale;
    auto clamp_round = [x](double lo, double hi) { return std::clamp(std::round(x), lo, hi); };
    switch (header.type) {
        case SampleType::u8: return clamp_round(0, 255);
        case SampleType::i8: return clamp_round(-128, 127);
        case SampleType::u16: return clamp_round(0, 65535);
        case SampleType::i16: return clamp_round(-32768, 32767);
        case SampleType::u32: return clamp_round(0, 4294967295.0);
        case SampleType::i32: return clamp_round(-2147483648.0, 2147483647.0);
        case SampleType::f32: return static_cast<float>(x);
        case SampleType::f64: return x;
    }
    return 0;
}

struct RoundTripCase {
    const char* file;
    SampleType type;
    ByteOrder order;
    bool analyze = false;   ///< header.format "analyze"
    bool gzip = false;      ///< WriteOptions::gzip (NRRD)
    bool geometry = true;   ///< the format stores an origin (false: OpenQVis, raw)
};

std::ostream& operator<<(std::ostream& out, const RoundTripCase& c) {
    return out << c.file << " " << to_string(c.type) << " " << to_string(c.order) << (c.analyze ? " analyze" : "")
               << (c.gzip ? " gzip" : "");
}

class WriteVolumeRoundTrip : public testing::TestWithParam<RoundTripCase> {};

TEST_P(WriteVolumeRoundTrip, ReadsBackWhatWasWritten) {
    const RoundTripCase& c = GetParam();
    test::ScratchDir dir;
    const PhantomSpec spec = small_phantom();
    // Analyze keeps the origin as a whole voxel: -2, 3 and -1 voxels here.
    const std::array<double, 3> origin = c.geometry ? std::array<double, 3>{-1, 2.25, -1.25} : std::array<double, 3>{};
    VolumeHeader header = header_for(c.type, c.order, origin);
    if (c.analyze) header.format = "analyze";
    WriteOptions options;
    options.gzip = c.gzip;
    const WriteResult result = write_volume(dir / c.file, header, slices_of(spec), options);
    ASSERT_FALSE(result.files.empty());
    for (const auto& file : result.files) EXPECT_TRUE(std::filesystem::exists(file)) << file;

    ReadOptions read_options;
    if (std::string(c.file).rfind(".raw") != std::string::npos) {
        read_options.raw_dims = header.dims;
        read_options.raw_type = c.type;
        read_options.raw_byte_order = c.order;
        read_options.raw_spacing = header.spacing;
    }
    const auto reader = open_volume(result.files.front(), read_options);
    const VolumeHeader& read = reader->header();
    EXPECT_EQ(read.dims, header.dims);
    EXPECT_EQ(read.type, header.type);
    if (sample_size(c.type) > 1) EXPECT_EQ(read.byte_order, c.order);
    for (int r = 0; r < 3; ++r) {
        EXPECT_NEAR(read.spacing[r], header.spacing[r], 1e-6);
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(read.index_to_world[r][k], header.index_to_world[r][k], 1e-6);
    }
    // Formats with a scale field give back the scale (as a float32 in NIfTI/Analyze).
    const double expected_scale = result.value_scale_stored ? header.value_scale : 1.0;
    EXPECT_NEAR(read.value_scale, expected_scale, 1e-7 * expected_scale);
    EXPECT_EQ(read.value_offset, 0.0);

    const std::vector<float> values = test::read_all(*reader);
    std::vector<float> slice(static_cast<std::size_t>(header.slice_voxels()));
    for (std::int64_t z = 0; z < header.dims[2]; ++z) {
        fill_phantom_slice(spec, z, slice.data());
        for (std::size_t i = 0; i < slice.size(); ++i) {
            const double expected = stored_value(slice[i], header) * read.value_scale + read.value_offset;
            const double got = values[static_cast<std::size_t>(z * header.slice_voxels()) + i];
            ASSERT_NEAR(got, expected, 1e-6 * std::max(1.0, std::abs(expected))) << "z " << z << " i " << i;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(
    EveryFormat, WriteVolumeRoundTrip,
    testing::Values(RoundTripCase{"a.nii", SampleType::u8, ByteOrder::little},
                    RoundTripCase{"a.nii.gz", SampleType::i16, ByteOrder::big},
                    RoundTripCase{"a.nii", SampleType::f64, ByteOrder::big},
                    RoundTripCase{"pair.hdr", SampleType::f32, ByteOrder::little},
                    RoundTripCase{"pair.img", SampleType::u16, ByteOrder::big},
                    RoundTripCase{"spm.hdr", SampleType::i16, ByteOrder::big, true},
                    RoundTripCase{"spm.hdr", SampleType::u8, ByteOrder::little, true},
                    RoundTripCase{"q.dat", SampleType::u8, ByteOrder::little, false, false, false},
                    RoundTripCase{"q.dat", SampleType::u16, ByteOrder::little, false, false, false},
                    RoundTripCase{"q.dat", SampleType::f32, ByteOrder::little, false, false, false},
                    RoundTripCase{"m.mhd", SampleType::i16, ByteOrder::big},
                    RoundTripCase{"m.mha", SampleType::u8, ByteOrder::little},
                    RoundTripCase{"m.mha", SampleType::f64, ByteOrder::little},
                    RoundTripCase{"n.nrrd", SampleType::u8, ByteOrder::little},
                    RoundTripCase{"n.nrrd", SampleType::i16, ByteOrder::big, false, true},
                    RoundTripCase{"n.nhdr", SampleType::f32, ByteOrder::little},
                    RoundTripCase{"n.nhdr", SampleType::u16, ByteOrder::big, false, true},
                    RoundTripCase{"r.raw", SampleType::i16, ByteOrder::big, false, false, false},
                    RoundTripCase{"r.raw.gz", SampleType::f32, ByteOrder::little, false, false, false},
                    RoundTripCase{"series/", SampleType::i16, ByteOrder::little},
                    RoundTripCase{"series/", SampleType::u8, ByteOrder::big}));

// ---- binary header fields ----

float f32_at(const Bytes& bytes, std::size_t offset) {
    float value;
    std::memcpy(&value, bytes.data() + offset, 4);
    return value;
}
std::int16_t i16_at(const Bytes& bytes, std::size_t offset) {
    std::int16_t value;
    std::memcpy(&value, bytes.data() + offset, 2);
    return value;
}

/// The affine nifti1.h rebuilds from the qform of a .nii: R from the quaternion (b, c, d) with
/// a = sqrt(1 - b^2 - c^2 - d^2), world = R * diag(pixdim1, pixdim2, qfac * pixdim3) * ijk + qoffset.
Affine qform_affine(const Bytes& bytes) {
    const double b = f32_at(bytes, 256), c = f32_at(bytes, 260), d = f32_at(bytes, 264);
    const double a = std::sqrt(std::max(0.0, 1 - b * b - c * c - d * d));
    const double R[3][3] = {{a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
                            {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
                            {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
    const double qfac = f32_at(bytes, 76);
    const double scale[3] = {f32_at(bytes, 80), f32_at(bytes, 84), qfac * f32_at(bytes, 88)};
    Affine m{};
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) m[r][k] = R[r][k] * scale[k];
        m[r][3] = f32_at(bytes, 268 + 4 * r);
    }
    return m;
}

/// Rotation by @a degrees about z of an anisotropic grid, axis @a flip (0..2) negated.
Affine rotated_affine(double degrees, int flip, const std::array<double, 3>& sp) {
    const double c = std::cos(degrees * 3.14159265358979323846 / 180), s = std::sin(degrees * 3.14159265358979323846 / 180);
    Affine m{{{c * sp[0], -s * sp[1], 0, 10}, {s * sp[0], c * sp[1], 0, -20}, {0, 0, sp[2], 30}}};
    for (int r = 0; r < 3; ++r) m[r][flip] = -m[r][flip];
    return m;
}

TEST(WriteVolumeTest, NiftiSformIsTheAffineAndQformRebuildsIt) {
    test::ScratchDir dir;
    VolumeHeader header = header_for(SampleType::u8, ByteOrder::little, {});
    header.index_to_world = rotated_affine(30, 2, header.spacing);  // left-handed: qfac -1
    write_volume(dir / "rot.nii", header, slices_of(small_phantom()));
    const Bytes bytes = test::read_bytes(dir / "rot.nii");
    ASSERT_EQ(bytes.size(), 352u + 13 * 11 * 7);
    EXPECT_EQ(std::memcmp(bytes.data() + 344, "n+1\0", 4), 0);
    EXPECT_EQ(f32_at(bytes, 108), 352.0f);               // vox_offset
    EXPECT_EQ(i16_at(bytes, 70), 2);                     // datatype u8
    EXPECT_FLOAT_EQ(f32_at(bytes, 112), 1.0f / 255);     // scl_slope
    EXPECT_EQ(i16_at(bytes, 252), 1);                    // qform_code
    EXPECT_EQ(i16_at(bytes, 254), 1);                    // sform_code
    EXPECT_EQ(f32_at(bytes, 76), -1.0f);                 // qfac
    const Affine q = qform_affine(bytes);
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) {
            EXPECT_FLOAT_EQ(f32_at(bytes, 280 + 16 * r + 4 * k), static_cast<float>(header.index_to_world[r][k]));
            EXPECT_NEAR(q[r][k], header.index_to_world[r][k], 1e-6) << r << k;  // float32 quaternion
        }
}

TEST(WriteVolumeTest, NiftiQformOfAHalfTurnIsAsGoodAsFloatAllows) {
    // Flipping x of a 30-degree turn leaves, after qfac, a rotation by 180 degrees: its
    // quaternion has a = 0, which NIfTI rebuilds as sqrt(1 - b^2 - c^2 - d^2) from float32
    // b, c, d, so a (and the matrix) carries an error up to sqrt(float eps) = 3.5e-4.
    test::ScratchDir dir;
    VolumeHeader header = header_for(SampleType::u8, ByteOrder::little, {});
    header.index_to_world = rotated_affine(30, 0, header.spacing);
    write_volume(dir / "flip.nii", header, slices_of(small_phantom()));
    const Affine q = qform_affine(test::read_bytes(dir / "flip.nii"));
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(q[r][k], header.index_to_world[r][k], 1e-3) << r << k;
}

TEST(WriteVolumeTest, AnalyzeKeepsTheSpmScaleAndOriginator) {
    test::ScratchDir dir;
    VolumeHeader header = header_for(SampleType::i16, ByteOrder::little, {-2.5, 0, -5});  // voxels 5, 0, 4 at world 0
    header.format = "analyze";
    const WriteResult result = write_volume(dir / "spm.hdr", header, slices_of(small_phantom()));
    ASSERT_EQ(result.files.size(), 2u);
    EXPECT_EQ(result.files[1], dir / "spm.img");
    const Bytes bytes = test::read_bytes(dir / "spm.hdr");
    ASSERT_EQ(bytes.size(), 348u);
    EXPECT_EQ(i16_at(bytes, 70), 4);                      // datatype i16
    EXPECT_FLOAT_EQ(f32_at(bytes, 112), 1.0f / 1000);     // funused1
    EXPECT_EQ(i16_at(bytes, 253), 6);                     // originator, 1-based
    EXPECT_EQ(i16_at(bytes, 255), 1);
    EXPECT_EQ(i16_at(bytes, 257), 5);
    EXPECT_EQ(std::filesystem::file_size(dir / "spm.img"), 13u * 11 * 7 * 2);
}

TEST(WriteVolumeTest, NrrdHeaderIsTextEndedByABlankLine) {
    test::ScratchDir dir;
    const VolumeHeader header = header_for(SampleType::u16, ByteOrder::big, {1, 2, 3});
    WriteOptions gzip;
    gzip.gzip = true;
    write_volume(dir / "n.nhdr", header, slices_of(small_phantom()), gzip);
    const Bytes text = test::read_bytes(dir / "n.nhdr");
    const std::string header_text(text.begin(), text.end());
    EXPECT_EQ(header_text.rfind("NRRD0004\n", 0), 0u);
    EXPECT_NE(header_text.find("type: uint16\n"), std::string::npos);
    EXPECT_NE(header_text.find("endian: big\n"), std::string::npos);
    EXPECT_NE(header_text.find("encoding: gzip\n"), std::string::npos);
    EXPECT_NE(header_text.find("space directions: (0.5,0,0) (0,0.75,0) (0,0,1.25)\n"), std::string::npos);
    EXPECT_NE(header_text.find("data file: n.raw.gz\n"), std::string::npos);
    EXPECT_EQ(header_text.substr(header_text.size() - 2), "\n\n");
    const Bytes data = test::read_bytes(dir / "n.raw.gz");
    ASSERT_GE(data.size(), 2u);
    EXPECT_EQ(data[0], 0x1f);
    EXPECT_EQ(data[1], 0x8b);
}

// ---- failures write nothing ----

TEST(WriteVolumeTest, AFailureMidwayLeavesNoFile) {
    for (const char* name : {"a.nii.gz", "pair.hdr", "m.mhd", "n.nrrd", "n.nhdr", "q.dat", "r.raw", "series/"}) {
        test::ScratchDir dir;
        const SliceSource failing = [](std::int64_t z, float* slice) {
            if (z == 3) throw Error("slice source failed");
            std::fill(slice, slice + 13 * 11, 0.5f);
        };
        EXPECT_THROW(write_volume(dir / name, header_for(SampleType::u8, ByteOrder::little, {}), failing), Error)
            << name;
        EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << name;
    }
}

TEST(WriteVolumeTest, RefusesWhatAFormatCannotHold) {
    test::ScratchDir dir;
    const SliceSource slices = slices_of(small_phantom());
    EXPECT_THROW(write_volume(dir / "q.dat", header_for(SampleType::i16, ByteOrder::little, {}), slices), Error);
    EXPECT_THROW(write_volume(dir / "q.dat", header_for(SampleType::u16, ByteOrder::big, {}), slices), Error);
    EXPECT_THROW(write_volume(dir / "q.dat", header_for(SampleType::u8, ByteOrder::little, {1, 0, 0}), slices), Error);
    VolumeHeader analyze = header_for(SampleType::u16, ByteOrder::little, {});
    analyze.format = "analyze";
    EXPECT_THROW(write_volume(dir / "spm.hdr", analyze, slices), Error);
    analyze.type = SampleType::u8;
    analyze.index_to_world[0][3] = 0.3;  // not a whole voxel
    EXPECT_THROW(write_volume(dir / "spm.hdr", analyze, slices), Error);
    VolumeHeader mismatch = header_for(SampleType::u8, ByteOrder::little, {});
    mismatch.spacing = {2, 2, 2};  // the affine still says 0.5, 0.75, 1.25
    EXPECT_THROW(write_volume(dir / "a.nii", mismatch, slices), Error);
    VolumeHeader zero_scale = header_for(SampleType::u8, ByteOrder::little, {});
    zero_scale.value_scale = 0;
    EXPECT_THROW(write_volume(dir / "a.nii", zero_scale, slices), Error);
    const VolumeHeader fine = header_for(SampleType::u8, ByteOrder::little, {});
    EXPECT_THROW(write_volume(dir / "a.xyz", fine, slices), UsageError);
    EXPECT_THROW(write_volume(dir / "a.mhd.gz", fine, slices), UsageError);
    WriteOptions gzip;
    gzip.gzip = true;
    EXPECT_THROW(write_volume(dir / "a.nii", fine, slices, gzip), UsageError);
    EXPECT_THROW(write_volume(dir / "missing" / "a.nii", fine, slices), Error);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// ---- streaming and determinism ----

TEST(WriteVolumeTest, SlicesAreAskedForOnceInOrder) {
    test::ScratchDir dir;
    std::vector<std::int64_t> asked;
    const SliceSource recording = [&](std::int64_t z, float* slice) {
        asked.push_back(z);
        std::fill(slice, slice + 13 * 11, 0.25f);
    };
    write_volume(dir / "a.nii.gz", header_for(SampleType::u8, ByteOrder::little, {}), recording);
    EXPECT_EQ(asked, (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6}));
}

TEST(WriteVolumeTest, SameSeedSameBytesAnyThreadCount) {
    test::ScratchDir dir;
    PhantomSpec spec = phantom_preset("cube-minus-sphere", {31, 27, 23});
    spec.noise_sigma = 0.1;
    spec.seed = 9;
    const VolumeHeader header = header_for(SampleType::i16, ByteOrder::big, {});
    VolumeHeader sized = header;
    sized.dims = spec.dims;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        write_volume(dir / "one.nii.gz", sized, slices_of(spec));
    }
    {
        tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
        write_volume(dir / "four.nii.gz", sized, slices_of(spec));
    }
    spec.seed = 10;
    write_volume(dir / "other.nii.gz", sized, slices_of(spec));
    const Bytes one = test::read_bytes(dir / "one.nii.gz");
    EXPECT_EQ(one, test::read_bytes(dir / "four.nii.gz"));
    EXPECT_NE(one, test::read_bytes(dir / "other.nii.gz"));
    EXPECT_EQ(one.at(0), 0x1f);  // gzip magic
    EXPECT_EQ(one.at(1), 0x8b);
}

// ---- the command ----

TEST(PhantomCommandTest, WritesADensityWhoseHalfLevelIsTheSurface) {
    test::ScratchDir dir;
    const auto out = dir / "s.nii.gz";
    ASSERT_EQ(cli::run({"phantom", "sphere", "--size", "24", "-o", out.string(), "--quiet"}), 0);
    const auto reader = open_volume(out);
    EXPECT_EQ(reader->header().dims, (std::array<std::int64_t, 3>{24, 24, 24}));
    const std::vector<float> values = test::read_all(*reader);
    // Sphere of radius 40 * 24 / 128 = 7.5 about 11.5: voxel 19 is 0 from the surface along x.
    EXPECT_NEAR(test::voxel(values, reader->header(), 19, 11, 11), phantom_density(phantom_preset("sphere", {24, 24, 24}), 19, 11.5, 11.5), 0.6 / 255);
    EXPECT_NEAR(test::voxel(values, reader->header(), 11, 11, 11), 1.0, 1e-6);
    EXPECT_NEAR(test::voxel(values, reader->header(), 0, 0, 0), 0.0, 1e-6);
}

TEST(PhantomCommandTest, OptionsReachTheFile) {
    test::ScratchDir dir;
    const auto out = dir / "t.nrrd";
    ASSERT_EQ(cli::run({"phantom", "torus", "--dims", "20,16,12", "--type", "i16", "--endian", "big", "--gzip",
                        "--spacing", "0.5,0.5,2", "--noise", "0.1", "--seed", "4", "-o", out.string(), "--quiet"}),
              0);
    const auto reader = open_volume(out);
    EXPECT_EQ(reader->header().dims, (std::array<std::int64_t, 3>{20, 16, 12}));
    EXPECT_EQ(reader->header().type, SampleType::i16);
    EXPECT_EQ(reader->header().byte_order, ByteOrder::big);
    EXPECT_DOUBLE_EQ(reader->header().spacing[2], 2.0);
}

TEST(PhantomCommandTest, BadArgumentsWriteNothing) {
    test::ScratchDir dir;
    const auto out = (dir / "x.nii").string();
    EXPECT_EQ(cli::run({"phantom", "dodecahedron", "-o", out, "--quiet"}), cli::kUsageError);
    EXPECT_EQ(cli::run({"phantom", "torus", "--tube-radius", "50", "-o", out, "--quiet"}), cli::kUsageError);
    EXPECT_EQ(cli::run({"phantom", "sphere", "--size", "8", "--dims", "8,8,8", "-o", out}), cli::kUsageError);
    EXPECT_EQ(cli::run({"phantom", "sphere", "--type", "u16", "-o", (dir / "x.dat").string(), "--quiet",
                        "--endian", "big"}),
              cli::kRuntimeError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(PhantomCommandTest, HelpListsTheShapes) {
    testing::internal::CaptureStdout();
    EXPECT_EQ(cli::run({"phantom", "--help"}), 0);
    const std::string help = testing::internal::GetCapturedStdout();
    for (const auto& name : phantom_preset_names()) EXPECT_NE(help.find(name), std::string::npos) << name;
}

}  // namespace
}  // namespace vdbmesh
