// Picks the reader for a path: a folder is a DICOM series, --raw-dims forces headerless
// raw, otherwise the extension decides (".gz" looked through).

#include <filesystem>
#include <string>

#include "formats.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

namespace {

/// The extension that names the format: ".nii" for "a.nii.gz", lower-cased.
std::string format_extension(const std::filesystem::path& path) {
    std::filesystem::path name = path.filename();
    if (detail::to_lower(name.extension().string()) == ".gz") name = name.stem();
    return detail::to_lower(name.extension().string());
}

/// Whether @a file lies in @a folder or below it, after resolving "..", "." and symbolic links.
bool inside_folder(const std::filesystem::path& file, const std::filesystem::path& folder) {
    std::error_code ec;
    const std::filesystem::path f = std::filesystem::weakly_canonical(file, ec);
    const std::filesystem::path d = std::filesystem::weakly_canonical(folder.empty() ? "." : folder, ec);
    const std::filesystem::path relative = f.lexically_relative(d);
    return !ec && !relative.empty() && *relative.begin() != "..";
}

/// Throws FormatError when a header names a data file outside its own folder, unless allowed.
VolumeSource checked_data_files(VolumeSource source, const std::filesystem::path& header, const std::string& field,
                                const ReadOptions& options) {
    if (options.allow_outside_data) return source;
    for (const DataSegment& segment : source.segments) {
        if (!inside_folder(segment.path, header.parent_path()))
            throw FormatError(header.string(), field,
                              "a data file in the header's folder (--allow-outside-data reads it anyway)",
                              "\"" + segment.path.string() + "\"");
    }
    return source;
}

std::string file_type_name(std::filesystem::file_type type) {
    switch (type) {
        case std::filesystem::file_type::fifo: return "a FIFO (named pipe)";
        case std::filesystem::file_type::socket: return "a socket";
        case std::filesystem::file_type::block: return "a block device";
        case std::filesystem::file_type::character: return "a character device";
        default: return "not a regular file";
    }
}

}  // namespace

VolumeSource open_volume_source(const std::filesystem::path& path, const ReadOptions& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return detail::read_dicom_series(path);
    const std::filesystem::file_type type = std::filesystem::status(path, ec).type();
    if (type != std::filesystem::file_type::not_found && type != std::filesystem::file_type::regular) {
        // A FIFO without a writer would block the first read for ever.
        throw FormatError(path.string(), "file", "a regular file (a scan is read with seeks)", file_type_name(type));
    }
    if (options.raw_dims) return detail::read_raw(path, options);
    if (!std::filesystem::exists(path, ec))
        throw FormatError(path.string(), "file", "an existing file", "nothing at that path");

    const std::string ext = format_extension(path);
    if (ext == ".nii" || ext == ".hdr" || ext == ".img") return detail::read_nifti_or_analyze(path);
    if (ext == ".dat") return checked_data_files(detail::read_openqvis(path), path, "ObjectFileName", options);
    if (ext == ".mhd" || ext == ".mha") return checked_data_files(detail::read_metaimage(path), path, "ElementDataFile", options);
    if (ext == ".nrrd" || ext == ".nhdr") return checked_data_files(detail::read_nrrd(path), path, "data file", options);
    if (ext == ".raw" || ext.empty())
        throw FormatError(path.string(), "format", "a header, or --raw-dims X,Y,Z for a headerless raw file",
                          "no header (extension \"" + ext + "\")");
    throw FormatError(path.string(), "extension",
                      "one of .nii .nii.gz .hdr .img .dat .mhd .mha .nrrd .nhdr .vdb, a DICOM folder, or --raw-dims",
                      "\"" + ext + "\"");
}

}  // namespace vdbmesh
