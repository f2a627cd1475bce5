// Parses the tags of one DICOM file that a volume needs (DICOM PS3.5: data set encoding,
// section 7; PS3.10: file format, section 7.1; PS3.3 C.7.6.2-3: image plane and pixel modules).
//
// GDCM (libgdcm) walks the data set: preamble or not, meta header or not, implicit or
// explicit VR, undefined-length sequences. It stops at Pixel Data without reading it
// (ReadUpToTag with Pixel Data also skipped), leaving the stream at the first byte of the
// pixel values; the element header just before that point is checked here so that the
// offset never rests on GDCM's behaviour alone. Values are decoded here with bounds checks.

#include "dicom_parse.h"

#include <gdcmDataSet.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>

#include <cstring>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#include "parse_util.h"
#include "vdbmesh/error.h"

namespace vdbmesh::detail {

namespace {

const gdcm::Tag kPixelData(0x7fe0, 0x0010);

/// A tag and its name for error messages: "Rows (0028,0010)".
struct Field {
    gdcm::Tag tag;
    const char* name;
};
const Field kSopClass{{0x0008, 0x0016}, "SOPClassUID (0008,0016)"};
const Field kSeriesUid{{0x0020, 0x000e}, "SeriesInstanceUID (0020,000E)"};
const Field kRows{{0x0028, 0x0010}, "Rows (0028,0010)"};
const Field kColumns{{0x0028, 0x0011}, "Columns (0028,0011)"};
const Field kBitsAllocated{{0x0028, 0x0100}, "BitsAllocated (0028,0100)"};
const Field kPixelRepresentation{{0x0028, 0x0103}, "PixelRepresentation (0028,0103)"};
const Field kSamplesPerPixel{{0x0028, 0x0002}, "SamplesPerPixel (0028,0002)"};
const Field kFrames{{0x0028, 0x0008}, "NumberOfFrames (0028,0008)"};
const Field kPosition{{0x0020, 0x0032}, "ImagePositionPatient (0020,0032)"};
const Field kOrientation{{0x0020, 0x0037}, "ImageOrientationPatient (0020,0037)"};
const Field kPixelSpacing{{0x0028, 0x0030}, "PixelSpacing (0028,0030)"};
const Field kSliceThickness{{0x0018, 0x0050}, "SliceThickness (0018,0050)"};
const Field kSlope{{0x0028, 0x1053}, "RescaleSlope (0028,1053)"};
const Field kIntercept{{0x0028, 0x1052}, "RescaleIntercept (0028,1052)"};

enum class Sniff { not_dicom, part10, bare };

/// "DICM" at byte 128 (PS3.10 7.1): a Part 10 file; or a bare data set whose first tag is in
/// group 0002 (meta header without preamble) or 0008 (identifying group), little- or big-endian.
Sniff sniff(std::istream& in) {
    unsigned char head[132] = {};
    in.seekg(0);
    in.read(reinterpret_cast<char*>(head), sizeof head);
    const std::streamsize got = in.gcount();
    in.clear();
    in.seekg(0);
    if (got == static_cast<std::streamsize>(sizeof head) && std::memcmp(head + 128, "DICM", 4) == 0) return Sniff::part10;
    if (got < 8) return Sniff::not_dicom;
    const unsigned group_le = head[0] | (head[1] << 8);
    const unsigned group_be = (head[0] << 8) | head[1];
    return group_le == 0x0002 || group_le == 0x0008 || group_be == 0x0008 ? Sniff::bare : Sniff::not_dicom;
}

/// Reads the values of one file's data set. GDCM keeps binary values (US) in host order
/// whatever the transfer syntax, and text values (IS, DS, UI) as written.
class TagValues {
public:
    TagValues(const gdcm::DataSet& data_set, const std::filesystem::path& file) : data_set_(data_set), file_(file) {}

    /// The raw bytes, or nothing when the element is absent, empty or a sequence.
    std::optional<std::string> bytes(const Field& field) const {
        if (!data_set_.FindDataElement(field.tag)) return std::nullopt;
        const gdcm::ByteValue* value = data_set_.GetDataElement(field.tag).GetByteValue();
        if (!value || value->GetLength() == 0 || !value->GetPointer()) return std::nullopt;
        return std::string(value->GetPointer(), value->GetLength());
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
        std::uint16_t value;
        std::memcpy(&value, raw->data(), 2);
        return value;
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
    const gdcm::DataSet& data_set_;
    const std::filesystem::path& file_;
};

/// Refuses the transfer syntaxes whose pixel data is not plain samples at a file offset.
ByteOrder check_transfer_syntax(const gdcm::TransferSyntax& syntax, const std::filesystem::path& file) {
    switch (syntax) {
        case gdcm::TransferSyntax::ImplicitVRLittleEndian:
        case gdcm::TransferSyntax::ExplicitVRLittleEndian: return ByteOrder::little;
        case gdcm::TransferSyntax::ExplicitVRBigEndian: return ByteOrder::big;
        default: break;
    }
    const char* uid = syntax.GetString();
    throw FormatError(file.string(), "TransferSyntaxUID (0002,0010)",
                      "uncompressed: 1.2.840.10008.1.2, 1.2.840.10008.1.2.1 or 1.2.840.10008.1.2.2",
                      std::string(uid ? uid : "an unknown syntax") + " (compressed or private syntaxes are not supported)");
}

/// Checks that the element header ending at @a value_offset is Pixel Data's and returns its
/// value length (the last 4 bytes of the header in every uncompressed syntax).
std::uint64_t pixel_data_length(std::istream& in, std::uint64_t value_offset, bool explicit_vr, ByteOrder order,
                                const std::filesystem::path& file) {
    const std::uint64_t header = explicit_vr ? 12 : 8;
    unsigned char bytes[12] = {};
    bool read = value_offset >= header;
    if (read) {
        in.clear();
        in.seekg(static_cast<std::streamoff>(value_offset - header));
        in.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(header));
        read = in.gcount() == static_cast<std::streamsize>(header);
    }
    const auto u16 = [&](int at) {
        return order == ByteOrder::little ? unsigned(bytes[at] | (bytes[at + 1] << 8)) : unsigned((bytes[at] << 8) | bytes[at + 1]);
    };
    if (!read || u16(0) != 0x7fe0 || u16(2) != 0x0010)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", "an element header before byte " + std::to_string(value_offset),
                          "other bytes");
    const int at = static_cast<int>(header) - 4;
    const std::uint32_t length = order == ByteOrder::little
                                     ? std::uint32_t(u16(at)) | (std::uint32_t(u16(at + 2)) << 16)
                                     : (std::uint32_t(u16(at)) << 16) | std::uint32_t(u16(at + 2));
    if (length == 0xffffffffu)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", "a defined length (uncompressed)", "undefined length (encapsulated)");
    return length;
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

void silence_gdcm_messages() {
    static std::once_flag once;
    std::call_once(once, [] {
        gdcm::Trace::SetDebug(false);
        gdcm::Trace::SetWarning(false);
        gdcm::Trace::SetError(false);
    });
}

std::optional<DicomSlice> parse_dicom_slice(std::istream& in, const std::filesystem::path& file) {
    const Sniff kind = sniff(in);
    if (kind == Sniff::not_dicom) return std::nullopt;
    silence_gdcm_messages();
    gdcm::Reader reader;
    reader.SetStream(in);
    const bool parsed = reader.ReadUpToTag(kPixelData, std::set<gdcm::Tag>{kPixelData});
    const std::uint64_t stop = reader.GetStreamCurrentPosition();  // the Pixel Data value, when found
    const gdcm::DataSet& data_set = reader.GetFile().GetDataSet();
    const bool image = data_set.FindDataElement(kRows.tag);
    if (!parsed) {
        // A file that merely starts like a bare data set is skipped; one that shows itself
        // as DICOM (magic, SOP class, image rows) is broken, not foreign.
        if (kind == Sniff::bare && !image && !data_set.FindDataElement(kSopClass.tag)) return std::nullopt;
        throw FormatError(file.string(), "data set", "DICOM elements up to Pixel Data (7FE0,0010)",
                          "bytes GDCM cannot parse (truncated or corrupt)");
    }
    if (!image) return std::nullopt;  // DICOM but not an image (a DICOMDIR, a report)
    const TagValues tags(data_set, file);

    DicomSlice slice;
    const gdcm::TransferSyntax& syntax = reader.GetFile().GetHeader().GetDataSetTransferSyntax();
    slice.byte_order = check_transfer_syntax(syntax, file);
    slice.transfer_syntax = syntax.GetString() ? syntax.GetString() : "";
    read_values(tags, slice, file);
    check_values(slice, file);

    slice.pixel_offset = stop;
    const std::uint64_t end = stream_size(in);
    if (slice.pixel_offset > end)
        throw FormatError(file.string(), "Pixel Data (7FE0,0010)", "present", "none before the end of the file");
    slice.pixel_length = pixel_data_length(in, slice.pixel_offset, syntax.IsExplicit(), slice.byte_order, file);
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
