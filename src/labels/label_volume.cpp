// Label maps in: the samples of a scan as 16-bit labels, and the voxels per label.

#include <cmath>
#include <string>

#include "vdbmesh/error.h"
#include "vdbmesh/labels.h"

namespace vdbmesh {
namespace {

/// Slices read per call: a few megabytes of floats for the scans we meet.
constexpr std::int64_t kSlabSlices = 8;

bool is_label_value(float v) { return v >= 0 && v <= float(kMaxLabel) && std::floor(v) == v; }

/// Calls @a visit(first_index, samples, count) for each slab of @a reader, from the start.
template <class Visit>
void for_each_slab(SliceReader& reader, const std::function<void(double)>& progress, Visit&& visit) {
    const VolumeHeader& h = reader.header();
    std::vector<float> slab(std::size_t(h.slice_voxels() * std::min(kSlabSlices, h.dims[2])));
    for (std::int64_t z = reader.next_slice(); z < h.dims[2];) {
        const std::int64_t slices = std::min(kSlabSlices, h.dims[2] - z);
        reader.read_slices(slices, slab.data());
        if (!visit(z * h.slice_voxels(), slab.data(), std::size_t(slices * h.slice_voxels()))) return;
        z += slices;
        if (progress) progress(double(z) / double(h.dims[2]));
    }
}

}  // namespace

LabelVolume read_label_volume(SliceReader& reader) {
    LabelVolume volume;
    volume.header = reader.header();
    volume.labels.resize(std::size_t(volume.header.voxel_count()));
    for_each_slab(reader, {}, [&](std::int64_t first, const float* samples, std::size_t count) {
        for (std::size_t i = 0; i < count; ++i) {
            if (!is_label_value(samples[i])) {
                const std::int64_t index = first + std::int64_t(i), sx = volume.header.dims[0], sy = volume.header.dims[1];
                throw FormatError(volume.header.path.string(),
                                  "sample (" + std::to_string(index % sx) + ", " + std::to_string(index / sx % sy) + ", " +
                                      std::to_string(index / (sx * sy)) + ")",
                                  "a label: an integer 0.." + std::to_string(kMaxLabel), std::to_string(samples[i]));
            }
            volume.labels[std::size_t(first) + i] = std::uint16_t(samples[i]);
        }
        return true;
    });
    return volume;
}

std::optional<std::vector<LabelCount>> count_labels(SliceReader& reader, std::size_t max_distinct,
                                                    const std::function<void(double)>& progress) {
    std::vector<std::uint64_t> counts(std::size_t(kMaxLabel) + 1, 0);
    std::size_t distinct = 0;
    bool labels = true;
    for_each_slab(reader, progress, [&](std::int64_t, const float* samples, std::size_t count) {
        for (std::size_t i = 0; i < count && labels; ++i) {
            if (!is_label_value(samples[i])) labels = false;
            else if (counts[std::size_t(samples[i])]++ == 0 && ++distinct > max_distinct) labels = false;
        }
        return labels;
    });
    if (!labels) return std::nullopt;
    std::vector<LabelCount> result;
    for (std::size_t v = 0; v < counts.size(); ++v)
        if (counts[v]) result.push_back({std::uint32_t(v), counts[v]});
    return result;
}

std::vector<LabelCount> count_labels(const LabelVolume& volume) {
    std::vector<std::uint64_t> counts(std::size_t(kMaxLabel) + 1, 0);
    for (std::uint16_t label : volume.labels) ++counts[label];
    std::vector<LabelCount> result;
    for (std::size_t v = 0; v < counts.size(); ++v)
        if (counts[v]) result.push_back({std::uint32_t(v), counts[v]});
    return result;
}

}  // namespace vdbmesh
