#include "shared_scan.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "test_data.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/read.h"

namespace vdbmesh::test {

const std::vector<SharedScan>& shared_scans() {
    static const std::vector<SharedScan> scans = {
        {"BunnyCt",
         {"raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part1of2.raw.gz",
          "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part2of2.raw.gz"},
         1200.5,
         std::array<std::int64_t, 3>{512, 512, 361}},
        {"CThead", {"raw_stanford_cthead/CThead_256x256x113_int16be.raw.gz"}, 600.5, std::array<std::int64_t, 3>{256, 256, 113}},
        {"EngineNifti", {"nifti_engine_ct/engine.nii.gz"}, 100.5, std::nullopt},
        {"WalnutOpenQVis", {"openqvis_walnut_ct/walnut.dat"}, 4084.5, std::nullopt},
        {"CtPitchNifti", {"nifti_ct_pitch_phantom/CT_pitch.nii.gz"}, 100.5, std::nullopt},
        {"Seg3dMrNifti", {"nifti_seg3d_mr_t1/MR.nii.gz"}, 200.5, std::nullopt},
        {"Spm12T1Nifti", {"nifti_spm12_single_subj_t1/single_subj_T1.nii"}, 0.5, std::nullopt},
        {"Spm2T1Analyze", {"analyze_spm2_single_subj_t1/spm2_single_subj_T1.hdr"}, 0.5, std::nullopt},
        {"HeadsqNrrd", {"raw_vtk_headsq/slices/quarter.nhdr"}, 1000.5, std::nullopt},
        {"EgsnrcDicomSeries", {"dicom_egsnrc_ct_phantom"}, 200.5, std::nullopt},
        {"NucleonOpenQVis", {"openqvis_nucleon_sim/nucleon.dat"}, 100.5, std::nullopt},
    };
    return scans;
}

const SharedScan& shared_scan(const std::string& name) {
    for (const SharedScan& scan : shared_scans()) {
        if (scan.name == name) return scan;
    }
    throw std::invalid_argument("no shared scan named " + name);
}

void open_shared_scan(const SharedScan& scan, OpenSlices& open) {
    std::vector<std::filesystem::path> paths;
    for (const std::string& input : scan.inputs) {
        VDBMESH_SHARED_DATA(path, input);
        paths.push_back(path);
    }
    ReadOptions read;
    if (scan.raw_i16_dims) {
        read.raw_dims = *scan.raw_i16_dims;
        read.raw_type = SampleType::i16;
        read.raw_byte_order = ByteOrder::big;
        read.raw_more_files.assign(paths.begin() + 1, paths.end());
    }
    open = [paths, read] { return std::unique_ptr<SliceReader>(open_volume(paths.front(), read)); };
}

void convert_shared_scan(const SharedScan& scan, openvdb::FloatGrid::Ptr& grid) {
    OpenSlices open;
    open_shared_scan(scan, open);
    if (!open) return;
    grid = convert_to_grid(*open(), shared_scan_options(scan));
}

ConvertOptions shared_scan_options(const SharedScan& scan) {
    ConvertOptions convert;
    convert.iso = scan.iso;
    return convert;
}

}  // namespace vdbmesh::test
