#pragma once
// A SliceReader handing out the negated samples of another: the object below a level is the
// object above its negative, the same surface (edge crossings are symmetric in the sign), and
// convert_to_grid closes its band at the scan's box for an object above the level only.

#include <cstdint>
#include <memory>
#include <utility>

#include "vdbmesh/read.h"

namespace vdbmesh::python {

class NegatedReader final : public SliceReader {
public:
    explicit NegatedReader(std::unique_ptr<SliceReader> source) : source_(std::move(source)) {}

    const VolumeHeader& header() const override { return source_->header(); }
    void read_slices(std::int64_t slices, float* out) override {
        source_->read_slices(slices, out);
        const std::int64_t count = slices * header().slice_voxels();
        for (std::int64_t i = 0; i < count; ++i) out[i] = -out[i];
    }
    std::int64_t next_slice() const override { return source_->next_slice(); }

private:
    std::unique_ptr<SliceReader> source_;
};

}  // namespace vdbmesh::python
