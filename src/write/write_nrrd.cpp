// NRRD writer (teem, "NRRD: Nearly Raw Raster Data", teem.sourceforge.net/nrrd/format.html,
// NRRD0004): a text header ended by a blank line, followed by the samples (.nrrd) or naming a
// "data file" (.nhdr), with "encoding: raw" or "gzip". The geometry is written as "space
// dimension: 3" with "space directions" (the affine's columns) and "space origin": the
// affine's world frame is not claimed to be any anatomical one. NRRD has no value scale field.

#include "vdbmesh/atomic_file.h"
#include "vdbmesh/error.h"
#include "volume_writers.h"

namespace vdbmesh::detail {

namespace {

const char* type_name(SampleType type) {
    switch (type) {
        case SampleType::u8: return "uint8";
        case SampleType::i8: return "int8";
        case SampleType::u16: return "uint16";
        case SampleType::i16: return "int16";
        case SampleType::u32: return "uint32";
        case SampleType::i32: return "int32";
        case SampleType::f32: return "float";
        case SampleType::f64: return "double";
    }
    return "";
}

/// "(x,y,z)"
std::string vector_text(double x, double y, double z) {
    return "(" + format_number(x) + "," + format_number(y) + "," + format_number(z) + ")";
}

std::string nrrd_header(const VolumeHeader& header, bool gzip, const std::string& data_file) {
    const Affine& m = header.index_to_world;
    std::string text = "NRRD0004\n# Complete NRRD file format specification at:\n"
                       "# http://teem.sourceforge.net/nrrd/format.html\n";
    text += std::string("type: ") + type_name(header.type) + "\n";
    text += "dimension: 3\nspace dimension: 3\n";
    text += "sizes: " + std::to_string(header.dims[0]) + " " + std::to_string(header.dims[1]) + " " +
            std::to_string(header.dims[2]) + "\n";
    text += "space directions: " + vector_text(m[0][0], m[1][0], m[2][0]) + " " +
            vector_text(m[0][1], m[1][1], m[2][1]) + " " + vector_text(m[0][2], m[1][2], m[2][2]) + "\n";
    text += "kinds: domain domain domain\n";
    if (sample_size(header.type) > 1) text += "endian: " + to_string(header.byte_order) + "\n";
    text += std::string("encoding: ") + (gzip ? "gzip" : "raw") + "\n";
    text += "space origin: " + vector_text(m[0][3], m[1][3], m[2][3]) + "\n";
    if (!header.units.empty())
        text += "space units: \"" + header.units + "\" \"" + header.units + "\" \"" + header.units + "\"\n";
    if (!data_file.empty()) text += "data file: " + data_file + "\n";
    return text + "\n";
}

}  // namespace

WriteResult write_nrrd(const std::filesystem::path& path, const VolumeHeader& header, const SliceSource& slices,
                       bool attached, bool gzip) {
    check_volume_header(path, header);
    if (attached && !gzip) {
        write_attached(path, nrrd_header(header, false, ""), false, header, slices);
        return {{path}, false};
    }
    if (attached) {
        // The header stays plain text; the samples after its blank line are one gzip stream.
        AtomicFile file(path);
        ByteSink text(file.temp_path(), path, false);
        text.write(nrrd_header(header, true, ""));
        text.close();
        ByteSink samples(file.temp_path(), path, true, true);
        write_samples(samples, header, slices);
        samples.close();
        file.commit();
        return {{path}, false};
    }
    const std::filesystem::path data_path = sibling(path, gzip ? ".raw.gz" : ".raw");
    write_detached(path, nrrd_header(header, gzip, data_path.filename().string()), data_path, gzip, header, slices);
    return {{path, data_path}, false};
}

}  // namespace vdbmesh::detail
