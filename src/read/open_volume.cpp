// Picks the reader for a path: a folder is a DICOM series, --raw-dims forces headerless
// raw, otherwise the extension decides (".gz" looked through).

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

}  // namespace

VolumeSource open_volume_source(const std::filesystem::path& path, const ReadOptions& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return detail::read_dicom_series(path);
    if (options.raw_dims) return detail::read_raw(path, options);
    if (!std::filesystem::exists(path, ec))
        throw FormatError(path.string(), "file", "an existing file", "nothing at that path");

    const std::string ext = format_extension(path);
    if (ext == ".nii" || ext == ".hdr" || ext == ".img") return detail::read_nifti_or_analyze(path);
    if (ext == ".dat") return detail::read_openqvis(path);
    if (ext == ".mhd" || ext == ".mha") return detail::read_metaimage(path);
    if (ext == ".nrrd" || ext == ".nhdr") return detail::read_nrrd(path);
    if (ext == ".raw" || ext.empty())
        throw FormatError(path.string(), "format", "a header, or --raw-dims X,Y,Z for a headerless raw file",
                          "no header (extension \"" + ext + "\")");
    throw FormatError(path.string(), "extension",
                      "one of .nii .nii.gz .hdr .img .dat .mhd .mha .nrrd .nhdr .vdb, a DICOM folder, or --raw-dims",
                      "\"" + ext + "\"");
}

}  // namespace vdbmesh
