// Converting a scan for the object on either side of the isovalue (side_grid.h).

#include "vdbmesh/side_grid.h"

#include <cstdint>

namespace vdbmesh {

namespace {

/// The negated samples of another reader.
class NegatedReader final : public SliceReader {
public:
    explicit NegatedReader(SliceReader& source) : source_(source) {}

    const VolumeHeader& header() const override { return source_.header(); }
    void read_slices(std::int64_t slices, float* out) override {
        source_.read_slices(slices, out);
        const std::int64_t count = slices * header().slice_voxels();
        for (std::int64_t i = 0; i < count; ++i) out[i] = -out[i];
    }
    std::int64_t next_slice() const override { return source_.next_slice(); }

private:
    SliceReader& source_;
};

}  // namespace

SideGrid convert_for_side(SliceReader& source, const ConvertOptions& options, Inside side) {
    SideGrid converted;
    if (side == Inside::above) {
        converted.grid = convert_to_grid(source, options);
        converted.iso = options.iso;
        return converted;
    }
    ConvertOptions negated_options = options;
    negated_options.iso = -options.iso;
    if (options.iso_range) negated_options.iso_range = std::make_pair(-options.iso_range->second, -options.iso_range->first);
    NegatedReader negated(source);
    converted.grid = convert_to_grid(negated, negated_options);
    converted.grid->insertMeta(kMetaNegatedSamples, openvdb::BoolMetadata(true));
    converted.iso = negated_options.iso;
    converted.negated = true;
    return converted;
}

bool holds_negated_samples(const openvdb::FloatGrid& grid) {
    const auto flag = grid.getMetadata<openvdb::BoolMetadata>(kMetaNegatedSamples);
    return flag && flag->value();
}

}  // namespace vdbmesh
