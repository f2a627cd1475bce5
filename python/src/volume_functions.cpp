// read_volume, mesh_array, mesh_file, array_to_vdb: scans and arrays through sparse grids.
// Arrays are streamed into the grid by ArraySliceReader, without a dense copy. The long calls
// check for Ctrl-C as they go (interrupt.h).

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "array_slice_reader.h"
#include "axis_order.h"
#include "bindings.h"
#include "inside_side.h"
#include "interrupt.h"
#include "mesh_arrays.h"
#include "vdbmesh/error.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/mesh_refusals.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/side_grid.h"

namespace py = pybind11;

namespace vdbmesh::python {

namespace {

/// What the array stands for in error messages.
constexpr const char* kArrayName = "array";

SampleType sample_type_of(const py::dtype& dtype) {
    if (dtype.byteorder() == '>' || (dtype.byteorder() == '<' && !PY_LITTLE_ENDIAN))
        throw UsageError("volume: expected an array in native byte order");
    const char kind = dtype.kind();
    const auto size = dtype.itemsize();
    if (kind == 'u' && size == 1) return SampleType::u8;
    if (kind == 'i' && size == 1) return SampleType::i8;
    if (kind == 'u' && size == 2) return SampleType::u16;
    if (kind == 'i' && size == 2) return SampleType::i16;
    if (kind == 'u' && size == 4) return SampleType::u32;
    if (kind == 'i' && size == 4) return SampleType::i32;
    if (kind == 'f' && size == 4) return SampleType::f32;
    if (kind == 'f' && size == 8) return SampleType::f64;
    throw UsageError("volume: expected a 3D array of uint8, int8, uint16, int16, uint32, int32, float32 or float64, got " +
                     py::str(static_cast<const py::handle&>(dtype)).cast<std::string>());
}

StridedVolume strided_volume(const py::array& array) {
    if (array.ndim() != 3) throw UsageError("volume: expected a 3D array, got " + std::to_string(array.ndim()) + "D");
    StridedVolume volume;
    volume.data = array.data();
    volume.type = sample_type_of(array.dtype());
    for (int axis = 0; axis < 3; ++axis) {
        volume.shape[axis] = array.shape(axis);
        volume.strides[axis] = array.strides(axis);
    }
    return volume;
}

MeshMethod parse_method(const std::string& name) {
    if (name == "dc") return MeshMethod::dc;
    if (name == "mc") return MeshMethod::mc;
    if (name == "openvdb") return MeshMethod::openvdb;
    throw UsageError("method: expected \"dc\", \"mc\" or \"openvdb\", got \"" + name + "\"");
}

Inside parse_inside(const std::string& name) {
    if (name == "above") return Inside::above;
    if (name == "below") return Inside::below;
    throw UsageError("inside: expected \"auto\", \"above\" or \"below\", got \"" + name + "\"");
}

/// The options of a mesh call, checking for Ctrl-C as the mesher goes; iso and inside are set later.
MeshOptions mesh_options(const std::string& method, double error, double adaptivity, bool open_boundary, bool sharp) {
    MeshOptions options;
    options.method = parse_method(method);
    options.error = error;
    options.adaptivity = adaptivity;
    options.open_boundary = open_boundary;
    options.sharp = sharp;
    options.progress = signal_checking_progress();
    return options;
}

/// The mesh of @a grid with at most @a triangles triangles (mesh_to_budget(), as `vdbmesh mesh
/// --triangles`), or the mesher's at options.error when no budget is given. Refused as
/// `vdbmesh mesh` refuses them (budget_refusal(); UsageError, a ValueError in Python): a budget
/// above the error-0 mesh's triangles, and one below where the guaranteed decimation has to stop.
Mesh mesh_within(const openvdb::FloatGrid& grid, const MeshOptions& options, std::optional<std::uint64_t> triangles) {
    if (!triangles) return mesh_grid(grid, options).mesh;
    BudgetReport budget;
    Mesh mesh = mesh_to_budget(grid, options, std::size_t(*triangles), &budget).mesh;
    if (mesh.triangles.empty()) return mesh;  // (no surface: mesh() raises vdbmesh.Error)
    const std::string refusal = budget_refusal(OptionStyle::python, *triangles, mesh.triangles.size(), budget);
    if (!refusal.empty()) throw UsageError(refusal);
    return mesh;
}

/// Converting at @a iso, checking for Ctrl-C as the conversion goes.
ConvertOptions convert_options(double iso) {
    ConvertOptions options;
    options.iso = iso;
    options.progress = signal_checking_progress();
    return options;
}

openvdb::FloatGrid::Ptr array_grid(const StridedVolume& volume, double iso, const Affine& array_to_world) {
    ArraySliceReader source(volume, array_to_world, kArrayName);
    return convert_to_grid(source, convert_options(iso));
}

/// A fresh reader of an array or a scan file, for each conversion.
using ReaderFactory = std::function<std::unique_ptr<SliceReader>()>;

/// The grid to mesh a source at @a level with the object on @a side (convert_for_side(): an
/// object below is the negated samples' object above -level, closed at the scan's box by every
/// method); sets options.iso and options.inside and says whether it negated the samples.
std::pair<openvdb::FloatGrid::Ptr, bool> side_grid(const ReaderFactory& reader, double level, Inside side,
                                                   MeshOptions& options) {
    const SideGrid converted = convert_for_side(*reader(), convert_options(level), side);
    options.iso = converted.iso;
    options.inside = converted.inside;
    return {converted.grid, converted.negated};
}

bool is_vdb_file(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".vdb";
}

/// The isovalue of a .vdb grid when none is given: the one convert stored, else 0 for a level set.
double stored_level(const openvdb::FloatGrid& grid, const std::filesystem::path& path) {
    if (const auto iso = stored_isovalue(grid)) return *iso;
    if (grid.getGridClass() == openvdb::GRID_LEVEL_SET) return 0.0;
    throw UsageError("level: required for " + path.string() + " (its grid records no isovalue)");
}

/// Throws UsageError when @a level lies outside the sample range a converted grid records
/// (there the surface would be the scan's box or nothing, as scikit-image refuses); @a negated:
/// the grid holds the negated samples.
void check_level_in_range(const openvdb::FloatGrid& grid, double level, bool negated, const std::filesystem::path& path) {
    const auto min = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMin);
    const auto max = grid.getMetadata<openvdb::DoubleMetadata>(kMetaValueMax);
    if (!min || !max) return;
    const double lo = negated ? -max->value() : min->value(), hi = negated ? -min->value() : max->value();
    if (level >= lo && level <= hi) return;
    throw UsageError("level: expected a value within the data range [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "] of " + path.string() + ", got " + std::to_string(level));
}

/// A scan file converted at @a level (checked against its data range) with the object on the
/// side @a inside names ("auto": decided on the grid as converted, converted again, negated,
/// for below); sets options.iso and options.inside.
openvdb::FloatGrid::Ptr scan_grid(const std::filesystem::path& path, double level, const std::string& inside,
                                  MeshOptions& options) {
    const auto reader = [&] { return open_volume(path); };
    openvdb::FloatGrid::Ptr grid;
    bool negated = false;
    if (inside != "auto") {
        std::tie(grid, negated) = side_grid(reader, level, parse_inside(inside), options);
    } else {
        grid = convert_to_grid(*reader(), convert_options(level));
        options.iso = level;
        options.inside = Inside::above;
        if (inside_away_from_border(*grid, level) == Inside::below)
            std::tie(grid, negated) = side_grid(reader, level, Inside::below, options);
    }
    check_level_in_range(*grid, level, negated, path);
    return grid;
}

/// A .vdb file's first float grid as stored, or a scan converted at @a level (required there);
/// sets options.iso and options.inside.
openvdb::FloatGrid::Ptr file_grid(const std::filesystem::path& path, std::optional<double> level,
                                  const std::string& inside, MeshOptions& options) {
    if (!is_vdb_file(path)) {
        if (!level) throw UsageError("level: required for a scan file (" + path.string() + "); `vdbmesh info` suggests one");
        return scan_grid(path, *level, inside, options);
    }
    openvdb::FloatGrid::Ptr grid = read_vdb(path);
    options.iso = level ? *level : stored_level(*grid, path);
    options.inside = inside == "auto" ? inside_away_from_border(*grid, options.iso) : parse_inside(inside);
    return grid;
}

/// The 4 x 4 matrix of @a affine.
py::array_t<double> affine_matrix(const Affine& affine) {
    py::array_t<double> matrix({4, 4});
    auto m = matrix.mutable_unchecked<2>();
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) m(row, col) = row < 3 ? affine[row][col] : (col == 3 ? 1.0 : 0.0);
    return matrix;
}

/// (array[z, y, x] float32, spacing, 4 x 4 affine), both in array axis order.
py::tuple read_volume(const std::filesystem::path& path) {
    std::unique_ptr<VolumeReader> reader;
    {
        py::gil_scoped_release released;
        reader = open_volume(path);
    }
    const VolumeHeader& header = reader->header();
    const std::array<std::int64_t, 3> shape = reversed(header.dims);
    py::array_t<float> samples({shape[0], shape[1], shape[2]});
    float* data = samples.mutable_data();
    {
        py::gil_scoped_release released;
        reader->read_slices(header.dims[2], data);
    }
    const std::array<double, 3> spacing = reversed(header.spacing);
    return py::make_tuple(samples, py::make_tuple(spacing[0], spacing[1], spacing[2]),
                          affine_matrix(swap_i_and_k(header.index_to_world)));
}

py::tuple mesh_array(const py::array& array, double level, const std::string& method, double error, double adaptivity,
                     const std::string& inside, bool open_boundary, const Affine& array_to_world,
                     std::optional<std::uint64_t> triangles, bool sharp) {
    MeshOptions options = mesh_options(method, error, adaptivity, open_boundary, sharp);
    const StridedVolume volume = strided_volume(array);
    Mesh mesh;
    {
        py::gil_scoped_release released;
        const auto reader = [&] { return std::make_unique<ArraySliceReader>(volume, array_to_world, kArrayName); };
        const Inside side = inside == "auto" ? inside_away_from_border(volume, level) : parse_inside(inside);
        mesh = mesh_within(*side_grid(reader, level, side, options).first, options, triangles);
    }
    return to_arrays(std::move(mesh));
}

py::tuple mesh_file(const std::filesystem::path& path, std::optional<double> level, const std::string& method,
                    double error, double adaptivity, const std::string& inside, bool open_boundary,
                    std::optional<std::uint64_t> triangles, bool sharp) {
    MeshOptions options = mesh_options(method, error, adaptivity, open_boundary, sharp);
    Mesh mesh;
    {
        py::gil_scoped_release released;
        mesh = mesh_within(*file_grid(path, level, inside, options), options, triangles);
    }
    return to_arrays(std::move(mesh));
}

/// Raises ValueError in `vdbmesh mesh --sharp`'s words when sharp=True cannot go with the
/// method, the error or a budget (sharp_refusal()).
void refuse_sharp_conflicts(bool sharp, const std::string& method, double error, bool budget) {
    const std::string refusal = sharp_refusal(OptionStyle::python, sharp, parse_method(method), error, budget);
    if (!refusal.empty()) throw UsageError(refusal);
}

void array_to_vdb(const py::array& array, double iso, const std::filesystem::path& path, const Affine& array_to_world) {
    const StridedVolume volume = strided_volume(array);
    py::gil_scoped_release released;
    write_vdb(*array_grid(volume, iso, array_to_world), path);
}

}  // namespace

void bind_volume_functions(py::module_& module) {
    module.def("read_volume", &read_volume, py::arg("path"));
    module.def("mesh_array", &mesh_array, py::arg("array"), py::arg("level"), py::arg("method"), py::arg("error"),
               py::arg("adaptivity"), py::arg("inside"), py::arg("open_boundary"), py::arg("array_to_world"), py::arg("triangles"),
               py::arg("sharp"));
    module.def("mesh_file", &mesh_file, py::arg("path"), py::arg("level"), py::arg("method"), py::arg("error"),
               py::arg("adaptivity"), py::arg("inside"), py::arg("open_boundary"), py::arg("triangles"), py::arg("sharp"));
    module.def("refuse_sharp_conflicts", &refuse_sharp_conflicts, py::arg("sharp"), py::arg("method"), py::arg("error"),
               py::arg("budget"));
    module.def("array_to_vdb", &array_to_vdb, py::arg("array"), py::arg("iso"), py::arg("path"),
               py::arg("array_to_world"));
}

}  // namespace vdbmesh::python
