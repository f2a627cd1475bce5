// write_volume(): picks the writer by the target's extension (".gz" looked through), or a
// DICOM series for a folder target. Each format lives in its own write_<format>.cpp.

#include "vdbmesh/write_volume.h"

#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"
#include "volume_writers.h"
#include "write_dicom.h"

namespace vdbmesh {

namespace {

bool is_folder_target(const std::filesystem::path& path) {
    const std::string text = path.string();
    std::error_code ec;
    return (!text.empty() && text.back() == '/') || std::filesystem::is_directory(path, ec);
}

}  // namespace

WriteResult write_volume(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                         const WriteOptions& options) {
    if (is_folder_target(path)) return detail::write_dicom_series(path, header, slices);

    std::filesystem::path name = path.filename();
    const bool gzip = detail::to_lower(name.extension().string()) == ".gz";
    if (gzip) name = name.stem();
    const std::string ext = detail::to_lower(name.extension().string());
    const bool nrrd = ext == ".nrrd" || ext == ".nhdr";
    if (options.gzip && !nrrd)
        throw UsageError(path.string() + ": gzip encoding is an NRRD option; other formats compress by name "
                                         "(.nii.gz, .raw.gz)");
    if (gzip && ext != ".nii" && ext != ".raw")
        throw UsageError(path.string() + ": only .nii.gz and .raw.gz are written gzipped (NRRD: use the gzip option)");

    if (ext == ".nii") return detail::write_nifti(path, header, slices, true, gzip);
    if (ext == ".hdr" || ext == ".img") {
        if (header.format == "analyze") return detail::write_analyze(path, header, slices);
        return detail::write_nifti(path, header, slices, false, false);
    }
    if (ext == ".dat") return detail::write_openqvis(path, header, slices);
    if (ext == ".mhd" || ext == ".mha") return detail::write_metaimage(path, header, slices, ext == ".mha");
    if (nrrd) return detail::write_nrrd(path, header, slices, ext == ".nrrd", options.gzip);
    if (ext == ".raw") return detail::write_raw(path, header, slices, gzip);
    throw UsageError(path.string() + ": cannot tell the output format from the extension \"" + ext +
                     "\": expected .nii .nii.gz .hdr .img .dat .mhd .mha .nrrd .nhdr .raw .raw.gz, or a folder/ "
                     "for DICOM");
}

}  // namespace vdbmesh
