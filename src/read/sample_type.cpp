#include <array>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/read.h"

namespace vdbmesh {

namespace {
struct TypeInfo {
    SampleType type;
    const char* name;
    std::size_t size;
};
constexpr std::array<TypeInfo, 8> kTypes{{{SampleType::u8, "u8", 1},
                                          {SampleType::i8, "i8", 1},
                                          {SampleType::u16, "u16", 2},
                                          {SampleType::i16, "i16", 2},
                                          {SampleType::u32, "u32", 4},
                                          {SampleType::i32, "i32", 4},
                                          {SampleType::f32, "f32", 4},
                                          {SampleType::f64, "f64", 8}}};
const TypeInfo& info(SampleType type) { return kTypes[static_cast<std::size_t>(type)]; }
}  // namespace

std::size_t sample_size(SampleType type) { return info(type).size; }
std::string to_string(SampleType type) { return info(type).name; }
std::string to_string(ByteOrder order) { return order == ByteOrder::little ? "little" : "big"; }

SampleType parse_sample_type(const std::string& name) {
    for (const auto& t : kTypes)
        if (name == t.name) return t.type;
    throw UsageError("unknown sample type \"" + name + "\": expected u8, i8, u16, i16, u32, i32, f32 or f64");
}

Affine axis_aligned_affine(const std::array<double, 3>& spacing, const std::array<double, 3>& origin) {
    Affine m{};
    for (int r = 0; r < 3; ++r) {
        m[r][r] = spacing[r];
        m[r][3] = origin[r];
    }
    return m;
}

}  // namespace vdbmesh
