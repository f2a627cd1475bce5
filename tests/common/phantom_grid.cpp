// Test helper: phantoms converted like scans (see phantom_grid.h).

#include "phantom_grid.h"

#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::test {

openvdb::FloatGrid::Ptr phantom_scan_grid(const PhantomSpec& spec) {
    const ScratchDir dir;
    VolumeHeader header;
    header.dims = spec.dims;
    header.type = SampleType::f32;
    write_volume(dir / "phantom.nii", header, [&](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); });
    auto reader = open_volume(dir / "phantom.nii");
    ConvertOptions options;
    options.iso = 0.5;
    return convert_to_grid(*reader, options);
}

}  // namespace vdbmesh::test
