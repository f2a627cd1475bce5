// vdbmesh_labels_bench ATLAS DIR...: judges folders of per-label meshes (`<value>[_name].stl|ply|obj`,
// as `vdbmesh mesh --labels -o DIR/` writes them, or bench/labels_vs_vtk.py for VTK's pipeline)
// against the label map ATLAS: per label CGAL's verdict (closed, manifold, outward,
// self-intersecting) and the volume error against its voxels; over all labels together the pairs
// of labels whose meshes cross other than by exactly shared faces (vertices welded by position
// across the labels, a triangle met in two labels counted once; CGAL's exact predicates,
// tests/common/cgal_judge.h). Prints one JSON object per folder. Issue 31.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "cgal_judge.h"
#include "vdbmesh/labels.h"
#include "vdbmesh/mesh_io.h"
#include "vdbmesh/read.h"

namespace {

using namespace vdbmesh;
using Json = nlohmann::ordered_json;

double voxel_volume(const Affine& m) {
    return std::abs(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                    m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]));
}

/// All labels' triangles in one soup, vertices welded by exact position, each triangle (as a
/// vertex set) once; per triangle the labels it came from.
struct Soup {
    Mesh mesh;
    std::vector<std::vector<std::uint32_t>> labels;
};

Soup weld(const std::map<std::uint32_t, Mesh>& meshes) {
    Soup soup;
    std::map<std::array<float, 3>, std::uint32_t> index;
    std::map<std::array<std::uint32_t, 3>, std::size_t> triangle;
    for (const auto& [label, mesh] : meshes)
        for (const auto& t : mesh.triangles) {
            std::array<std::uint32_t, 3> ids;
            for (int k = 0; k < 3; ++k) {
                const auto [it, fresh] = index.emplace(mesh.vertices[t[k]], std::uint32_t(soup.mesh.vertices.size()));
                if (fresh) soup.mesh.vertices.push_back(mesh.vertices[t[k]]);
                ids[k] = it->second;
            }
            std::array<std::uint32_t, 3> key = ids;
            std::sort(key.begin(), key.end());
            const auto [it, fresh] = triangle.emplace(key, soup.mesh.triangles.size());
            if (fresh) soup.mesh.triangles.push_back(ids), soup.labels.push_back({});
            soup.labels[it->second].push_back(label);
        }
    return soup;
}

Json judge_folder(const std::filesystem::path& folder, const LabelVolume& atlas) {
    std::map<std::uint32_t, Mesh> meshes;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        const std::string name = entry.path().filename().string();
        if (name.empty() || !std::isdigit(static_cast<unsigned char>(name[0]))) continue;
        meshes[std::uint32_t(std::stoul(name))] = read_mesh(entry.path());
    }
    std::vector<std::uint64_t> voxels(std::size_t(kMaxLabel) + 1, 0);
    for (const LabelCount& c : count_labels(atlas)) voxels[c.value] = c.voxels;
    const double one = voxel_volume(atlas.header.index_to_world);
    std::size_t clean = 0, self_intersecting = 0, not_closed_manifold = 0, volume_misses = 0, over_1000 = 0;
    double worst = 0;
    for (const auto& [label, mesh] : meshes) {
        const test::CgalVerdict v = test::judge_with_cgal(mesh);
        clean += v.clean();
        self_intersecting += v.self_intersects;
        not_closed_manifold += !(v.polygon_mesh && v.closed);
        if (voxels[label] > 1000) {
            ++over_1000;
            const double error = std::abs(v.volume - double(voxels[label]) * one) / (double(voxels[label]) * one);
            worst = std::max(worst, error);
            volume_misses += error > 0.02;
        }
    }
    const Soup soup = weld(meshes);
    std::set<std::pair<std::uint32_t, std::uint32_t>> crossing_labels;
    std::size_t crossing_triangles = 0;
    for (const auto& [i, j] : test::cgal_crossing_pairs(soup.mesh))
        for (std::uint32_t a : soup.labels[i])
            for (std::uint32_t b : soup.labels[j])
                if (a != b) crossing_labels.insert({std::min(a, b), std::max(a, b)}), ++crossing_triangles;
    Json j;
    j["folder"] = folder.string();
    j["labels"] = meshes.size();
    j["triangles"] = soup.mesh.triangles.size();
    j["cgal_clean_labels"] = clean;
    j["self_intersecting_labels"] = self_intersecting;
    j["not_closed_manifold_labels"] = not_closed_manifold;
    j["crossing_label_pairs"] = crossing_labels.size();
    j["crossing_triangle_pairs_between_labels"] = crossing_triangles;
    j["labels_over_1000_voxels"] = over_1000;
    j["volume_misses_over_2pct"] = volume_misses;
    j["worst_volume_error"] = worst;
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::cerr << "usage: vdbmesh_labels_bench ATLAS DIR...\n";
        return 2;
    }
    auto reader = open_volume(argv[1]);
    const LabelVolume atlas = read_label_volume(*reader);
    for (int i = 2; i < argc; ++i) std::cout << judge_folder(argv[i], atlas).dump() << "\n";
    return 0;
}
