// Walks the elements of a DICOM file (DICOM PS3.10 section 7.1: preamble, "DICM", meta
// header; PS3.5 section 7.1: element = tag, VR (explicit only), value length, value; the
// VRs OB OD OF OL OV OW SQ SV UC UN UR UT UV have 2 reserved bytes and a 32-bit length,
// the others a 16-bit length; section 7.5: sequence items (FFFE,E000) and the item and
// sequence delimiters (FFFE,E00D), (FFFE,E0DD), which never carry a VR; PS3.5 section
// 6.2.2 note: an undefined-length UN holds implicit VR little-endian items).
//
// Every read is checked against the stream's size and every step moves forward, so any
// input ends: at Pixel Data, at the end of the stream, or with a reason in `broken`.

#include "dicom_data_set.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace vdbmesh::detail {

namespace {

constexpr DicomTag kItem = dicom_tag(0xfffe, 0xe000);
constexpr DicomTag kItemEnd = dicom_tag(0xfffe, 0xe00d);
constexpr DicomTag kSequenceEnd = dicom_tag(0xfffe, 0xe0dd);
constexpr DicomTag kPixelData = dicom_tag(0x7fe0, 0x0010);
constexpr DicomTag kTransferSyntax = dicom_tag(0x0002, 0x0010);
constexpr std::uint64_t kPreambleBytes = 132;  // 128-byte preamble + "DICM"
/// Deeper nesting is refused (real files nest a few levels; this bounds the recursion).
constexpr int kMaxDepth = 32;

const std::string kImplicitLittle = "1.2.840.10008.1.2";
const std::string kExplicitLittle = "1.2.840.10008.1.2.1";
const std::string kExplicitBig = "1.2.840.10008.1.2.2";
const std::string kDeflated = "1.2.840.10008.1.2.1.99";

struct Encoding {
    bool explicit_vr = true;
    ByteOrder order = ByteOrder::little;
};

/// One element header.
struct Element {
    DicomTag tag = 0;
    std::string vr;  ///< "" in implicit VR and for items and delimiters
    std::uint64_t value_offset = 0;
    std::uint32_t length = 0;
};

/// Thrown inside this file when the walk cannot go on; read_dicom_header() records the reason.
struct Broken {
    std::string why;
};

std::string tag_name(DicomTag tag) {
    char text[16];
    std::snprintf(text, sizeof text, "(%04X,%04X)", static_cast<unsigned>(tag >> 16), static_cast<unsigned>(tag & 0xffff));
    return text;
}

bool is_capital(unsigned char c) { return c >= 'A' && c <= 'Z'; }

/// The explicit VRs with 2 reserved bytes and a 32-bit value length.
bool has_long_length(const std::string& vr) {
    static const std::set<std::string> kLong = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ",
                                                "SV", "UC", "UN", "UR", "UT", "UV"};
    return kLong.count(vr) > 0;
}

/// Bounds-checked reads from the stream.
class Bytes {
public:
    explicit Bytes(std::istream& in) : in_(in) {
        in_.clear();
        in_.seekg(0, std::ios::end);
        const std::streamoff end = in_.tellg();
        size_ = end > 0 ? static_cast<std::uint64_t>(end) : 0;
    }
    std::uint64_t size() const { return size_; }

    /// Copies @a count bytes from @a offset; false when they run past the end.
    bool read(std::uint64_t offset, void* out, std::size_t count) {
        if (offset > size_ || count > size_ - offset) return false;
        in_.clear();
        in_.seekg(static_cast<std::streamoff>(offset));
        in_.read(static_cast<char*>(out), static_cast<std::streamsize>(count));
        return in_.gcount() == static_cast<std::streamsize>(count);
    }
    void need(std::uint64_t offset, void* out, std::size_t count, const std::string& what) {
        if (!read(offset, out, count))
            throw Broken{what + " at byte " + std::to_string(offset) + " cut off by the end of the file"};
    }

private:
    std::istream& in_;
    std::uint64_t size_ = 0;
};

class Walker {
public:
    explicit Walker(std::istream& in) : bytes_(in) {}
    Bytes& bytes() { return bytes_; }

    /// The element header at @a at.
    Element element_at(std::uint64_t at, const Encoding& encoding) {
        unsigned char h[12];
        bytes_.need(at, h, 8, "an element header");
        const auto u16 = [&](int i) {
            return encoding.order == ByteOrder::little ? static_cast<std::uint32_t>(h[i] | (h[i + 1] << 8))
                                                       : static_cast<std::uint32_t>((h[i] << 8) | h[i + 1]);
        };
        const auto u32 = [&](int i) {
            return encoding.order == ByteOrder::little ? u16(i) | (u16(i + 2) << 16) : (u16(i) << 16) | u16(i + 2);
        };
        Element element;
        element.tag = (u16(0) << 16) | u16(2);
        element.value_offset = at + 8;
        if (!encoding.explicit_vr || element.tag >> 16 == 0xfffe) {
            element.length = u32(4);
            return element;
        }
        if (!is_capital(h[4]) || !is_capital(h[5]))
            throw Broken{"no VR (two capital letters) for " + tag_name(element.tag) + " at byte " + std::to_string(at)};
        element.vr.assign(reinterpret_cast<const char*>(h + 4), 2);
        if (!has_long_length(element.vr)) {
            element.length = u16(6);
            return element;
        }
        bytes_.need(at, h, 12, "an element header");
        element.length = u32(8);
        element.value_offset = at + 12;
        return element;
    }

    /// The offset just past a defined-length value, which must lie within the stream.
    std::uint64_t value_end(const Element& element) const {
        if (element.length > bytes_.size() - std::min(bytes_.size(), element.value_offset))
            throw Broken{"the " + std::to_string(element.length) + "-byte value of " + tag_name(element.tag) +
                         " cut off by the end of the file"};
        return element.value_offset + element.length;
    }

    /// The offset just past the element's value, walking through sequences of undefined length.
    std::uint64_t skip(const Element& element, const Encoding& encoding, int depth) {
        if (element.length != kDicomUndefinedLength) return value_end(element);
        if (encoding.explicit_vr && element.vr != "SQ" && element.vr != "UN")
            throw Broken{"an undefined length on " + tag_name(element.tag) + " (VR " + element.vr + ")"};
        const bool implicit_un = encoding.explicit_vr && element.vr == "UN";
        return skip_sequence(element.value_offset, implicit_un ? Encoding{false, ByteOrder::little} : encoding, depth + 1);
    }

    /// Items up to the sequence delimiter; returns the offset past it.
    std::uint64_t skip_sequence(std::uint64_t at, const Encoding& encoding, int depth) {
        if (depth > kMaxDepth) throw Broken{"sequences nested more than " + std::to_string(kMaxDepth) + " deep"};
        for (;;) {
            const Element item = element_at(at, encoding);
            if (item.tag == kSequenceEnd) return item.value_offset;
            if (item.tag != kItem)
                throw Broken{"an item (FFFE,E000) or sequence delimiter in a sequence, got " + tag_name(item.tag) +
                             " at byte " + std::to_string(at)};
            if (item.length != kDicomUndefinedLength) {
                at = value_end(item);
                continue;
            }
            for (at = item.value_offset;;) {
                const Element element = element_at(at, encoding);
                if (element.tag == kItemEnd) {
                    at = element.value_offset;
                    break;
                }
                at = skip(element, encoding, depth);
            }
        }
    }

    /// The group 0002 elements from @a at; returns where the data set starts.
    std::uint64_t read_meta(std::uint64_t at, DicomHeader& header) {
        const Encoding meta{looks_explicit(at), ByteOrder::little};
        unsigned char group[2];
        while (bytes_.read(at, group, 2) && group[0] == 0x02 && group[1] == 0x00) {
            const Element element = element_at(at, meta);
            if (element.length == kDicomUndefinedLength)
                throw Broken{"an undefined length in the meta header, on " + tag_name(element.tag)};
            const std::uint64_t end = value_end(element);
            if (element.tag == kTransferSyntax) header.transfer_syntax = text_value(element);
            header.meta_header = true;
            at = end;
        }
        return at;
    }

    /// The data set's encoding: from the transfer syntax, else from its first element.
    Encoding data_set_encoding(std::uint64_t at, DicomHeader& header) {
        Encoding encoding;
        if (header.transfer_syntax.empty()) {
            unsigned char group[2] = {0, 0};
            bytes_.read(at, group, 2);
            encoding.order = group[0] == 0x00 && group[1] == 0x08 ? ByteOrder::big : ByteOrder::little;
            encoding.explicit_vr = looks_explicit(at);
            if (!encoding.explicit_vr && encoding.order == ByteOrder::big)
                throw Broken{"implicit VR big-endian elements (not a DICOM encoding)"};
            header.transfer_syntax = !encoding.explicit_vr                  ? kImplicitLittle
                                     : encoding.order == ByteOrder::little ? kExplicitLittle
                                                                           : kExplicitBig;
        } else if (header.transfer_syntax == kDeflated) {
            throw Broken{"a deflated data set (" + kDeflated + "), not supported"};
        } else {
            // Every other syntax, the compressed ones included, encodes the data set in explicit VR little-endian.
            encoding.explicit_vr = header.transfer_syntax != kImplicitLittle;
            encoding.order = header.transfer_syntax == kExplicitBig ? ByteOrder::big : ByteOrder::little;
        }
        header.byte_order = encoding.order;
        return encoding;
    }

    /// The top-level elements from @a at up to Pixel Data or the end.
    void read_data_set(std::uint64_t at, const Encoding& encoding, const std::set<DicomTag>& wanted, DicomHeader& header) {
        while (at < bytes_.size()) {
            const Element element = element_at(at, encoding);
            if (element.tag == kPixelData) {
                header.pixel_offset = element.value_offset;
                header.pixel_length = element.length;
                return;
            }
            if (element.tag >> 16 == 0xfffe)
                throw Broken{"an item or delimiter " + tag_name(element.tag) + " outside a sequence at byte " + std::to_string(at)};
            const std::uint64_t end = skip(element, encoding, 0);
            if (wanted.count(element.tag) && element.length != kDicomUndefinedLength)
                header.values[element.tag] = raw_value(element);
            at = end;
        }
    }

private:
    /// True when the two bytes after the tag at @a at are capital letters (an explicit VR).
    bool looks_explicit(std::uint64_t at) {
        unsigned char vr[2] = {0, 0};
        return bytes_.read(at + 4, vr, 2) && is_capital(vr[0]) && is_capital(vr[1]);
    }
    std::string raw_value(const Element& element) {
        std::string value(element.length, '\0');
        bytes_.need(element.value_offset, value.data(), value.size(), "the value of " + tag_name(element.tag));
        return value;
    }
    /// A UI value without its NUL or space padding.
    std::string text_value(const Element& element) {
        std::string value = raw_value(element);
        while (!value.empty() && (value.back() == '\0' || value.back() == ' ')) value.pop_back();
        return value;
    }

    Bytes bytes_;
};

}  // namespace

std::optional<DicomHeader> read_dicom_header(std::istream& in, const std::set<DicomTag>& wanted) {
    Walker walker(in);
    DicomHeader header;
    unsigned char head[kPreambleBytes] = {};
    header.part10 = walker.bytes().read(0, head, kPreambleBytes) && std::memcmp(head + 128, "DICM", 4) == 0;
    if (!header.part10) {
        if (!walker.bytes().read(0, head, 8)) return std::nullopt;
        const unsigned group_little = head[0] | (head[1] << 8), group_big = (head[0] << 8) | head[1];
        if (group_little != 0x0002 && group_little != 0x0008 && group_big != 0x0008) return std::nullopt;
    }
    try {
        const std::uint64_t start = walker.read_meta(header.part10 ? kPreambleBytes : 0, header);
        const Encoding encoding = walker.data_set_encoding(start, header);
        walker.read_data_set(start, encoding, wanted, header);
    } catch (const Broken& broken) {
        header.broken = broken.why;
    }
    return header;
}

}  // namespace vdbmesh::detail
