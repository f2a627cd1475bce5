// Reads a folder holding one DICOM series as a volume (DICOM PS3.3 C.7.6.2, image plane
// module; C.11.1, modality LUT). Each file is one slice, parsed by dicom_parse.cpp. The
// slices are ordered by their position along the slice normal (the cross product of the
// row and column direction cosines), never by file name, and must form one series with a
// uniform spacing: a gap is reported as missing slices, not silently stretched.
//
// Geometry (LPS patient coordinates, mm): column i runs along the row direction cosines with
// the spacing between columns (PixelSpacing[1]), row j along the column cosines with the
// spacing between rows (PixelSpacing[0]), slice k along the normal.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "dicom_parse.h"
#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

using Vec3 = std::array<double, 3>;

/// Relative tolerance on slice spacing: more than this is a gap (missing slices).
constexpr double kSpacingTolerance = 0.01;
/// Tolerance on direction cosines (unit length, orthogonality, equality across slices):
/// scanners write them with about 6 decimals.
constexpr double kCosineTolerance = 1e-4;

struct SliceFile {
    std::filesystem::path path;
    DicomSlice slice;
    double along_normal = 0;  ///< dot(normal, ImagePositionPatient)
};

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", value);
    return text;
}

template <std::size_t N>
std::string numbers(const std::array<double, N>& values) {
    return join_values(values, "\\", number);
}

bool nearly_equal(double a, double b, double relative) {
    return std::abs(a - b) <= relative * std::max({1.0, std::abs(a), std::abs(b)});
}

/// The DICOM image files of @a folder in name order (for deterministic messages); other files are skipped.
std::vector<SliceFile> parse_folder(const std::filesystem::path& folder) {
    std::error_code ec;
    std::vector<std::filesystem::path> paths;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
        if (it->is_regular_file(ec)) paths.push_back(it->path());
    if (ec) throw FormatError(folder.string(), "cannot list the folder (" + ec.message() + ")");
    std::sort(paths.begin(), paths.end());

    std::vector<SliceFile> files;
    for (const std::filesystem::path& path : paths) {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw FormatError(path.string(), "cannot open the file");
        if (std::optional<DicomSlice> slice = parse_dicom_slice(in, path)) files.push_back({path, std::move(*slice)});
    }
    if (files.empty())
        throw FormatError(folder.string(), "DICOM files", "at least one DICOM image",
                          "none among " + std::to_string(paths.size()) + " files");
    return files;
}

/// Compares one field of every slice with the first one's.
class SeriesCheck {
public:
    SeriesCheck(const std::filesystem::path& folder, const SliceFile& first) : folder_(folder), first_(first) {}

    void same(const SliceFile& file, const std::string& field, const std::string& expected, const std::string& actual) const {
        if (expected != actual)
            throw FormatError(folder_.string(), field + " of " + file.path.filename().string(),
                              expected + " (as in " + first_.path.filename().string() + ", one series)", actual);
    }
    template <std::size_t N>
    void close(const SliceFile& file, const std::string& field, const std::optional<std::array<double, N>>& expected,
               const std::optional<std::array<double, N>>& actual, double relative) const {
        bool equal = expected.has_value() == actual.has_value();
        for (std::size_t i = 0; equal && expected && i < N; ++i)
            equal = nearly_equal((*expected)[i], (*actual)[i], relative);
        if (!equal) same(file, field, expected ? numbers(*expected) : "absent", actual ? numbers(*actual) : "absent");
    }

private:
    const std::filesystem::path& folder_;
    const SliceFile& first_;
};

/// One series: same UID, image size, sample type, byte order, orientation, spacing and rescale.
void check_one_series(const std::filesystem::path& folder, const std::vector<SliceFile>& files) {
    const SliceFile& first = files.front();
    const DicomSlice& a = first.slice;
    const SeriesCheck check(folder, first);
    for (const SliceFile& file : files) {
        const DicomSlice& b = file.slice;
        check.same(file, "SeriesInstanceUID (0020,000E)", a.series_uid, b.series_uid);
        check.same(file, "Rows (0028,0010)", std::to_string(a.rows), std::to_string(b.rows));
        check.same(file, "Columns (0028,0011)", std::to_string(a.columns), std::to_string(b.columns));
        check.same(file, "BitsAllocated (0028,0100)", std::to_string(a.bits_allocated), std::to_string(b.bits_allocated));
        check.same(file, "PixelRepresentation (0028,0103)", std::to_string(a.pixel_representation),
                   std::to_string(b.pixel_representation));
        check.same(file, "TransferSyntaxUID (0002,0010) byte order", to_string(a.byte_order), to_string(b.byte_order));
        check.close(file, "ImageOrientationPatient (0020,0037)", a.orientation, b.orientation, kCosineTolerance);
        check.close(file, "PixelSpacing (0028,0030)", a.pixel_spacing, b.pixel_spacing, 1e-6);
        check.close(file, "RescaleSlope (0028,1053)", std::optional(std::array{a.rescale_slope}),
                    std::optional(std::array{b.rescale_slope}), 1e-9);
        check.close(file, "RescaleIntercept (0028,1052)", std::optional(std::array{a.rescale_intercept}),
                    std::optional(std::array{b.rescale_intercept}), 1e-9);
    }
}

/// The unit row and column direction cosines, checked orthonormal.
std::array<Vec3, 2> directions(const SliceFile& file) {
    const std::array<double, 6>& o = *file.slice.orientation;
    const Vec3 row{o[0], o[1], o[2]}, column{o[3], o[4], o[5]};
    const double row_length = std::sqrt(dot(row, row)), column_length = std::sqrt(dot(column, column));
    if (std::abs(row_length - 1) > 1e-3 || std::abs(column_length - 1) > 1e-3 ||
        std::abs(dot(row, column)) > 1e-3 * row_length * column_length)
        throw FormatError(file.path.string(), "ImageOrientationPatient (0020,0037)", "two orthogonal unit vectors", numbers(o));
    Vec3 unit_row, unit_column;
    for (int c = 0; c < 3; ++c) {
        unit_row[c] = row[c] / row_length;
        unit_column[c] = column[c] / column_length;
    }
    return {unit_row, unit_column};
}

/// Sorts along the normal and returns the slice spacing; throws on duplicated positions or a gap.
double sort_along_normal(const std::filesystem::path& folder, std::vector<SliceFile>& files, const Vec3& normal) {
    for (SliceFile& file : files) file.along_normal = dot(normal, *file.slice.position);
    std::stable_sort(files.begin(), files.end(),
                     [](const SliceFile& a, const SliceFile& b) { return a.along_normal < b.along_normal; });
    const double extent = files.back().along_normal - files.front().along_normal;
    const double mean = extent / static_cast<double>(files.size() - 1);
    double smallest = extent;
    for (std::size_t k = 1; k < files.size(); ++k)
        smallest = std::min(smallest, files[k].along_normal - files[k - 1].along_normal);

    const auto describe = [](const SliceFile& file) {
        return file.path.filename().string() + " (" + number(file.along_normal) + " mm)";
    };
    for (std::size_t k = 1; k < files.size(); ++k)
        if (files[k].along_normal - files[k - 1].along_normal <= kSpacingTolerance * mean)
            throw FormatError(folder.string(), "ImagePositionPatient (0020,0032)", "one slice per position along the normal",
                              "duplicated slice position: " + describe(files[k - 1]) + " and " + describe(files[k]));
    for (std::size_t k = 1; k < files.size(); ++k) {
        const double step = files[k].along_normal - files[k - 1].along_normal;
        if (step > smallest * (1 + kSpacingTolerance))
            throw FormatError(folder.string(), "ImagePositionPatient (0020,0032)",
                              "uniform slice spacing " + number(smallest) + " mm (within 1%)",
                              "a gap of " + number(step) + " mm between " + describe(files[k - 1]) + " and " +
                                  describe(files[k]) + ": missing slices");
    }
    return mean;
}

/// Header geometry from the slices (sorted here).
void set_geometry(const std::filesystem::path& folder, std::vector<SliceFile>& files, VolumeHeader& header) {
    const DicomSlice& first = files.front().slice;
    if (first.pixel_spacing) {
        header.spacing[0] = (*first.pixel_spacing)[1];  // between columns: along a row, x
        header.spacing[1] = (*first.pixel_spacing)[0];  // between rows: along a column, y
    } else {
        header.warnings.push_back("no PixelSpacing (0028,0030): assumed 1 mm");
    }
    Vec3 row{1, 0, 0}, column{0, 1, 0}, origin{0, 0, 0};
    if (files.size() == 1) {
        header.spacing[2] = first.slice_thickness.value_or(1.0);
        if (first.orientation) {
            const std::array<Vec3, 2> unit = directions(files.front());
            row = unit[0];
            column = unit[1];
        }
        if (first.position) origin = *first.position;
        if (!first.orientation || !first.position)
            header.warnings.push_back("single slice without ImagePositionPatient/ImageOrientationPatient: axis-aligned at 0");
    } else {
        for (const SliceFile& file : files)
            if (!file.slice.orientation || !file.slice.position)
                throw FormatError(folder.string(), "ImagePositionPatient (0020,0032) and ImageOrientationPatient (0020,0037)",
                                  "present in every slice (they order the slices)",
                                  "absent in " + file.path.filename().string());
        const std::array<Vec3, 2> unit = directions(files.front());
        row = unit[0];
        column = unit[1];
        header.spacing[2] = sort_along_normal(folder, files, cross(row, column));
        origin = *files.front().slice.position;
    }
    const Vec3 normal = cross(row, column);
    Vec3 step;  // from one slice to the next: along the normal unless the gantry was tilted
    for (int c = 0; c < 3; ++c)
        step[c] = files.size() == 1 ? normal[c] * header.spacing[2]
                                    : ((*files.back().slice.position)[c] - origin[c]) / static_cast<double>(files.size() - 1);
    const Vec3 across = cross(step, normal);
    if (std::sqrt(dot(across, across)) > kSpacingTolerance * header.spacing[2])
        header.warnings.push_back("slice positions are not along the slice normal (gantry tilt?): the affine is sheared");
    for (int r = 0; r < 3; ++r)
        header.index_to_world[r] = {row[r] * header.spacing[0], column[r] * header.spacing[1], step[r], origin[r]};
}

}  // namespace

VolumeSource read_dicom_series(const std::filesystem::path& folder) {
    std::vector<SliceFile> files = parse_folder(folder);
    check_one_series(folder, files);

    VolumeSource source;
    VolumeHeader& header = source.header;
    header.format = "dicom";
    header.path = folder;
    header.units = "mm";
    const DicomSlice& first = files.front().slice;
    header.type = first.sample_type();
    header.byte_order = first.byte_order;
    header.dims = {first.columns, first.rows, static_cast<std::int64_t>(files.size())};
    check_dims(folder, "Columns, Rows, slices", header.dims, sample_size(header.type));
    header.value_scale = first.rescale_slope;
    header.value_offset = first.rescale_intercept;
    set_geometry(folder, files, header);

    for (const SliceFile& file : files) {
        DataSegment segment;
        segment.path = file.path;
        segment.offset = file.slice.pixel_offset;
        segment.bytes = file.slice.frame_bytes();
        segment.compression = Compression::none;  // compressed transfer syntaxes are refused by the parser
        segment.allow_trailing = true;  // elements may follow Pixel Data (padding); the parser checked its length
        source.segments.push_back(std::move(segment));
    }
    return source;
}

}  // namespace vdbmesh::detail
