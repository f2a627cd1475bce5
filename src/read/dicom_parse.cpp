// Parses the tags of one DICOM file that a volume needs (DICOM PS3.5: data set encoding,
// section 7; PS3.10: file format, section 7.1; PS3.3 C.7.6.2-3: image plane and pixel modules).
//
// dicom_data_set.cpp walks the elements (preamble or not, meta header or not, implicit or
// explicit VR, sequences) up to Pixel Data with bounds checks; the values it keeps are
// decoded here, with bounds checks too.

#include "dicom_parse.h"


#include <sstream>
#include <vector>

#include "dicom_data_set.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

/// A tag and its name for error messages: "Rows (0028,0010)".
struct Field {
    DicomTag tag;
    const char* name;
};
const Field kSopClass{dicom_tag(0x0008, 0x0016), "SOPClassUID (0008,0016)"};
const Field kSeriesUid{dicom_tag(0x0020, 0x000e), "SeriesInstanceUID (0020,000E)"};
const Field kRows{dicom_tag(0x0028, 0x0010), "Rows (0028,0010)"};
const Field kColumns{dicom_tag(0x0028, 0x0011), "Columns (0028,0011)"};
const Field kBitsAllocated{dicom_tag(0x0028, 0x0100), "BitsAllocated (0028,0100)"};
const Field kPixelRepresentation{dicom_tag(0x0028, 0x0103), "PixelRepresentation (0028,0103)"};
const Field kSamplesPerPixel{dicom_tag(0x0028, 0x0002), "SamplesPerPixel (0028,0002)"};
const Field kFrames{dicom_tag(0x0028, 0x0008), "NumberOfFrames (0028,0008)"};
const Field kPosition{dicom_tag(0x0020, 0x0032), "ImagePositionPatient (0020,0032)"};
const Field kOrientation{dicom_tag(0x0020, 0x0037), "ImageOrientationPatient (0020,0037)"};
const Field kPixelSpacing{dicom_tag(0x0028, 0x0030), "PixelSpacing (0028,0030)"};
const Field kSliceThickness{dicom_tag(0x0018, 0x0050), "SliceThickness (0018,0050)"};
const Field kSlope{dicom_tag(0x0028, 0x1053), "RescaleSlope (0028,1053)"};
const Field kIntercept{dicom_tag(0x0028, 0x1052), "RescaleIntercept (0028,1052)"};
const Field kAllFields[] = {kSopClass, kSeriesUid, kRows, kColumns, kBitsAllocated, kPixelRepresentation,
                            kSamplesPerPixel, kFrames, kPosition, kOrientation, kPixelSpacing,
                            kSliceThickness, kSlope, kIntercept};

std::set<DicomTag> wanted_tags() {
    std::set<DicomTag> tags;
    for (const Field& field : kAllFields) tags.insert(field.tag);
    return tags;
}

/// Reads the top-level values of one file's data set: binary values (US) in the data set's
/// byte order, text values (IS, DS, UI) as written.
class TagValues {
public:
    TagValues(const DicomHeader& header, const std::filesystem::path& file) : header_(header), file_(file) {}

    /// The raw bytes, or nothing when the element is absent or empty.
    std::optional<std::string> bytes(const Field& field) const {
        const auto found = header_.values.find(field.tag);
        if (found == header_.values.end() || found->second.empty()) return std::nullopt;
        return found->second;
    }

    /// Text without the space or NUL padding.
    std::optional<std::string> text(const Field& field) const {
        std::optional<std::string> raw = bytes(field);
        if (!raw) return std::nullopt;
        const auto last = raw->find_last_not_of(std::string(" \0", 2));
        if (last == std::string::npos) return std::nullopt;
        const auto first = raw->find_first_not_of(' ');
        return raw->substr(first, last - first + 1);
    }

    /// An unsigned short (VR US, one value).
    std::optional<int> us(const Field& field) const {
        std::optional<std::string> raw = bytes(field);
        if (!raw) return std::nullopt;
        if (raw->size() != 2) throw FormatError(file_.string(), field.name, "a 2-byte US value", std::to_string(raw->size()) + " bytes");
        const auto byte = [&](int i) { return static_cast<unsigned char>((*raw)[i]); };
        return header_.byte_order == ByteOrder::little ? byte(0) | (byte(1) << 8) : (byte(0) << 8) | byte(1);
    }

    int required_us(const Field& field) const {
        std::optional<int> value = us(field);
        if (!value) throw FormatError(file_.string(), field.name, "a value", "none");
        return *value;
    }

    /// Exactly @a N backslash-separated decimal strings (VR DS).
    template <std::size_t N>
    std::optional<std::array<double, N>> numbers(const Field& field) const {
        std::optional<std::string> raw = text(field);
        if (!raw) return std::nullopt;
        std::vector<std::string_view> parts;
        std::string_view rest = *raw;
        for (auto cut = rest.find('\\'); cut != std::string_view::npos; cut = rest.find('\\')) {
            parts.push_back(rest.substr(0, cut));
            rest.remove_prefix(cut + 1);
        }
        parts.push_back(rest);
        if (parts.size() != N)
            throw FormatError(file_.string(), field.name, std::to_string(N) + " values", std::to_string(parts.size()));
        std::array<double, N> values{};
        for (std::size_t i = 0; i < N; ++i) values[i] = parse_double(file_, field.name, parts[i]);
        return values;
    }

private:
    const DicomHeader& header_;
    const std::filesystem::path& file_;
};

/// Refuses the transfer syntaxes whose pixel data is not plain samples at a file offset.
ByteOrder check_transfer_syntax(const std::string& uid, const std::filesystem::path& file) {
    if (uid == "1.2.840.10008.1.2" || uid == "1.2.840.10008.1.2.1") return ByteOrder::little;
    if (uid == "1.2.840.10008.1.2.2") return ByteOrder::big;
    throw FormatError(file.string(), "TransferSyntaxUID (0002,0010)",
                      "uncompressed: 1.2.840.10008.1.2, 1.2.840.10008.1.2.1 or 1.2.840.10008.1.2.2",
                      "\"" + uid.substr(0, 64) + "\" (compressed or private syntaxes are not supported)");
}

std::uint64_t stream_size(std::istream& in) {
    in.clear();
    in.seekg(0, std::ios::end);
    const std::streamoff end = in.tellg();
    return end > 0 ? static_cast<std::uint64_t>(end) : 0;
}

/// The image pixel module (PS3.3 C.7.6.3) and image plane module (C.7.6.2) values.
void read_values(const TagValues& tags, DicomSlice& slice, const std::filesystem::path& file) {
    slice.series_uid = tags.text(kSeriesUid).value_or("");
    slice.rows = tags.required_us(kRows);
    slice.columns = tags.required_us(kColumns);
    slice.bits_allocated = tags.required_us(kBitsAllocated);
    slice.pixel_representation = tags.us(kPixelRepresentation).value_or(0);
    slice.samples_per_pixel = tags.us(kSamplesPerPixel).value_or(1);
    if (std::optional<std::string> frames = tags.text(kFrames)) slice.frames = parse_int(file, kFrames.name, *frames);
    slice.position = tags.numbers<3>(kPosition);
    slice.orientation = tags.numbers<6>(kOrientation);
    slice.pixel_spacing = tags.numbers<2>(kPixelSpacing);
    if (auto thickness = tags.numbers<1>(kSliceThickness)) slice.slice_thickness = (*thickness)[0];
    if (auto slope = tags.numbers<1>(kSlope)) slice.rescale_slope = (*slope)[0];
    if (auto intercept = tags.numbers<1>(kIntercept)) slice.rescale_intercept = (*intercept)[0];
}

/// What a volume reader can use: single-frame grayscale 8/16/32-bit samples.
void check_values(const DicomSlice& slice, const std::filesystem::path& file) {
    const std::string name = file.string();
    if (slice.rows < 1) throw FormatError(name, kRows.name, ">= 1", std::to_string(slice.rows));
    if (slice.columns < 1) throw FormatError(name, kColumns.name, ">= 1", std::to_string(slice.columns));
    if (slice.bits_allocated != 8 && slice.bits_allocated != 16 && slice.bits_allocated != 32)
        throw FormatError(name, kBitsAllocated.name, "8, 16 or 32", std::to_string(slice.bits_allocated));
    if (slice.pixel_representation != 0 && slice.pixel_representation != 1)
        throw FormatError(name, kPixelRepresentation.name, "0 or 1", std::to_string(slice.pixel_representation));
    if (slice.samples_per_pixel != 1)
        throw FormatError(name, kSamplesPerPixel.name, "1 (grayscale)", std::to_string(slice.samples_per_pixel));
    if (slice.frames != 1)
        throw FormatError(name, kFrames.name, "1 (single-frame images)", std::to_string(slice.frames));
    if (slice.rescale_slope == 0.0) throw FormatError(name, kSlope.name, "a non-zero value", "0");
    if (slice.pixel_spacing && !((*slice.pixel_spacing)[0] > 0 && (*slice.pixel_spacing)[1] > 0))
        throw FormatError(name, kPixelSpacing.name, "two values > 0",
                          std::to_string((*slice.pixel_spacing)[0]) + "\\" + std::to_string((*slice.pixel_spacing)[1]));
}

}  // namespace

SampleType DicomSlice::sample_type() const {
    const bool is_signed = pixel_representation == 1;
    switch (bits_allocated) {
        case 8: return is_signed ? SampleType::i8 : SampleType::u8;
        case 16: return is_signed ? SampleType::i16 : SampleType::u16;
        default: return is_signed ? SampleType::i32 : SampleType::u32;
    }
}

std::uint64_t DicomSlice::frame_bytes() const {
    return static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(columns) *
           static_cast<std::uint64_t>(samples_per_pixel) * static_cast<std::uint64_t>(bits_allocated / 8);
}

std::optional<DicomSlice> parse_dicom_slice(std::istream& in, const std::filesystem::path& file) {
    const std::optional<DicomHeader> header = read_dicom_header(in, wanted_tags());
    if (!header) return std::nullopt;
    const bool image = header->values.count(kRows.tag) > 0;
    if (!header->broken.empty()) {
        // A file that merely starts like a bare data set is skipped; one that shows itself
        // as DICOM (magic, SOP class, image rows) is broken, not foreign.
        if (!header->part10 && !image && !header->values.count(kSopClass.tag)) return std::nullopt;
        throw FormatError(file.string(), "data set", "DICOM elements up to Pixel Data (7FE0,0010)",
                          header->broken + " (truncated or corrupt)");
    }
    if (!image) return std::nullopt;  // DICOM but not an image (a DICOMDIR, a report)
    const TagValues tags(*header, file);

    DicomSlice slice;
    slice.byte_order = check_transfer_syntax(header->transfer_syntax, file);
    slice.transfer_syntax = header->transfer_syntax;
    read_values(tags, slice, file);
    check_values(slice, file);

    if (!header->pixel_offset)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", "present", "none before the end of the file");
    slice.pixel_offset = *header->pixel_offset;
    slice.pixel_length = header->pixel_length;
    if (slice.pixel_length == kDicomUndefinedLength)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", "a defined length (uncompressed)",
                          "undefined length (encapsulated)");
    const std::uint64_t end = stream_size(in);
    const std::uint64_t needed = slice.frame_bytes() * static_cast<std::uint64_t>(slice.frames);
    if (slice.pixel_length < needed)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010) length", "at least " + std::to_string(needed) + " bytes",
                          std::to_string(slice.pixel_length));
    if (end - slice.pixel_offset < needed)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", std::to_string(needed) + " bytes",
                          std::to_string(end - slice.pixel_offset) + " before the end of the file (truncated)");
    return slice;
}

std::optional<DicomSlice> parse_dicom_slice(const unsigned char* data, std::size_t size, const std::filesystem::path& file) {
    std::istringstream in(size > 0 ? std::string(reinterpret_cast<const char*>(data), size) : std::string());
    return parse_dicom_slice(in, file);
}

}  // namespace vdbmesh::detail
