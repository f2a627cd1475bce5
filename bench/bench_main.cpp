// vdbmesh_bench: conversion and meshing speed on the real scans of the shared data folder and
// on large phantoms, as ratios against OpenVDB measured in the same run (copyFromDense for
// conversion, volumeToMesh for meshing), throughput, peak memory and 1/2-thread scaling.
//
// Every measurement runs in its own forked child process, so that ru_maxrss (a per-process
// high-water mark) belongs to that measurement alone and nothing one stage allocated (or TBB's
// thread pool) carries into the next. The parent never starts TBB or OpenVDB before forking.
// In a child the stages run in a fixed order (conversion, then each mesher setting in the
// order printed), and the memory printed for a mesher is the process peak after it: the
// conversion's grid plus the largest mesh made so far. Both conversions also report CPU time
// (steadier than wall time on a shared machine) and their grid's size in memory and as a
// .vdb file (written last, into a temporary folder).
//
// Usage: vdbmesh_bench [--scans bunny,cthead,engine,walnut] [--phantom-sizes 256,512]
//                      [--errors 0,0.1,0.25,1] [--adaptivities 0,0.1,0.25,1]
//                      [--threads 1,2] [--budgets 1,2]
// --budgets: after the volumeToMesh meshes, the triangle budget at each one's triangle count by
// route 1 (mesh_to_budget(), `mesh --triangles`: DC at error 2, then the guaranteed decimator)
// and route 2 (DC at error 1, then the decimator), each measured with its volumeToMesh mesh
// against the trilinear isosurface (compare.h, 100,000 samples each way) and by analyze_mesh().

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "shared_data_dir.h"
#include "vdbmesh/analysis.h"
#include "vdbmesh/compare.h"
#include "vdbmesh/grid.h"
#include "vdbmesh/mesh_budget.h"
#include "vdbmesh/mesher.h"
#include "vdbmesh/phantom.h"
#include "vdbmesh/read.h"
#include "vdbmesh/write_volume.h"

namespace vdbmesh::bench {
namespace {

using Json = nlohmann::ordered_json;

/// Otsu's threshold that `vdbmesh info` suggests for the walnut (the others: issue 4's isovalues).
constexpr double kWalnutIso = 4084.5;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr int kRunsPerMesher = 2;

struct Scan {
    std::string name;
    std::filesystem::path file;
    ReadOptions read;
    double iso = 0;
};

/// Route 2 of the budget: DC at this error, then the decimator (route 1 starts at kBudgetBaseError).
constexpr double kRoute2Error = 1;

struct Setting {
    MeshMethod method;
    double value = 0;  ///< error (DC) or adaptivity (volumeToMesh; a budget's: the mesh whose count it meets)
    int budget_route = 0;  ///< 1 or 2: a triangle budget (--budgets) at the count of setting budget_of
    std::size_t budget_of = 0;
    std::string label() const {
        std::ostringstream text;
        if (budget_route != 0) return "budget " + std::to_string(budget_route) + " <= a=" + (text << value, text.str());
        text << (method == MeshMethod::dc ? "dc e=" : method == MeshMethod::mc ? "mc" : "openvdb a=");
        if (method != MeshMethod::mc) text << value;
        return text.str();
    }
};

/// The mesh of @a s: a mesher setting, or a budget of @a budget triangles by its route.
MeshResult mesh_setting(const openvdb::FloatGrid& grid, const Setting& s, MeshOptions options, std::size_t budget) {
    if (s.budget_route == 1) return mesh_to_budget(grid, options, budget);
    if (s.budget_route == 0) return mesh_grid(grid, options);
    options.error = kRoute2Error;
    MeshResult result = mesh_grid(grid, options);
    const auto start = Clock::now();
    DecimateOptions decimate;
    decimate.target_triangles = budget;
    result.mesh = decimate_mesh(result.mesh, decimate);
    result.report.phases.push_back({"decimate", seconds_since(start)});
    return result;
}

/// The figures of a mesh the budget table compares: distance to the trilinear isosurface (voxels),
/// share of angles under 10 degrees, and whether it is clean.
Json accuracy_figures(const TrueSurface& truth, const Mesh& mesh) {
    const MeshAnalysis analysis = analyze_mesh(mesh);
    return {{"hausdorff", truth.measure(mesh).distance.hausdorff},
            {"small_angle_share", analysis.small_angle_share},
            {"clean", analysis.is_clean()}};
}


double peak_rss_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

double cpu_seconds_since(std::clock_t start) { return double(std::clock() - start) / CLOCKS_PER_SEC; }

/// A converted grid's size in memory and, written with write_vdb to @a file, on disk.
Json grid_figures(const openvdb::FloatGrid& grid, const std::filesystem::path& file) {
    const auto start = Clock::now();
    write_vdb(grid, file);
    const double write_seconds = seconds_since(start);
    const double vdb_mb = double(std::filesystem::file_size(file)) / 1e6;
    std::filesystem::remove(file);
    return {{"active_voxels", grid.activeVoxelCount()},
            {"leaves", grid.tree().leafCount()},
            {"grid_mb", double(grid.memUsage()) / 1e6},
            {"write_seconds", write_seconds},
            {"vdb_mb", vdb_mb}};
}

/// Runs @a job in a forked child and returns the JSON it produced ({"failed": message} when it died).
Json run_forked(const std::function<Json()>& job) {
    int fds[2];
    if (pipe(fds) != 0) return Json{{"failed", "pipe"}};
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        std::string text;
        try {
            openvdb::initialize();
            text = job().dump();
        } catch (const std::exception& e) {
            text = Json{{"failed", e.what()}}.dump();
        }
        for (std::size_t done = 0; done < text.size();) {
            const ssize_t n = write(fds[1], text.data() + done, text.size() - done);
            if (n <= 0) break;
            done += std::size_t(n);
        }
        _exit(0);
    }
    close(fds[1]);
    std::string text;
    char buffer[4096];
    for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (text.empty()) return Json{{"failed", "child exited with status " + std::to_string(status)}};
    return Json::parse(text);
}

/// Child: convert with convert_to_grid, then mesh with every setting, on @a threads threads.
Json convert_and_mesh(const Scan& scan, const std::vector<Setting>& settings, int threads,
                      const std::filesystem::path& scratch) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    Json result;
    auto start = Clock::now();
    const std::clock_t cpu_start = std::clock();
    auto reader = open_volume(scan.file, scan.read);
    ConvertOptions convert;
    convert.iso = scan.iso;
    const openvdb::FloatGrid::Ptr grid = convert_to_grid(*reader, convert);
    result["convert_seconds"] = seconds_since(start);
    result["convert_cpu_seconds"] = cpu_seconds_since(cpu_start);
    result["active_voxels"] = grid->activeVoxelCount();
    result["convert_peak_mb"] = peak_rss_mb();
    const bool budgets = std::any_of(settings.begin(), settings.end(), [](const Setting& s) { return s.budget_route != 0; });
    std::optional<TrueSurface> truth;
    if (budgets) truth.emplace(*grid, scan.iso, Inside::above);
    for (const Setting& s : settings) {
        MeshOptions options;
        options.method = s.method;
        options.iso = scan.iso;
        (s.method == MeshMethod::openvdb ? options.adaptivity : options.error) = s.value;
        // The better of two runs: the first mesher timed would otherwise also pay for the
        // process's first touch of the memory its mesh needs, which later ones reuse.
        double best = std::numeric_limits<double>::infinity();
        std::size_t triangles = 0;
        MeshReport best_report;
        const std::size_t budget = s.budget_route ? result["meshes"][s.budget_of]["triangles"].get<std::size_t>() : 0;
        Mesh mesh;
        for (int run = 0; run < kRunsPerMesher; ++run) {
            start = Clock::now();
            MeshResult meshed = mesh_setting(*grid, s, options, budget);
            const double seconds = seconds_since(start);
            if (seconds < best) best_report = meshed.report;
            best = std::min(best, seconds);
            triangles = meshed.mesh.triangles.size();
            mesh = std::move(meshed.mesh);
        }
        Json phases = Json::array();
        for (const MeshPhase& phase : best_report.phases) phases.push_back({phase.name, phase.seconds});
        result["meshes"].push_back({{"seconds", best},
                                    {"triangles", triangles},
                                    {"peak_mb", peak_rss_mb()},
                                    {"phases", phases}});
        if (truth && (s.method == MeshMethod::openvdb || s.budget_route != 0)) result["meshes"].back()["accuracy"] = accuracy_figures(*truth, mesh);
    }
    // Last, so that writing leaves the conversion's and the meshers' peaks as they were.
    result["grid"] = grid_figures(*grid, scratch / "sparse.vdb");
    return result;
}

/// Child: the dense route, read every sample into openvdb::tools::Dense, then copyFromDense
/// (voxels equal to the background, the scan's minimum, stay inactive).
Json dense_route(const Scan& scan, int threads, const std::filesystem::path& scratch) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    auto start = Clock::now();
    const std::clock_t cpu_start = std::clock();
    auto reader = open_volume(scan.file, scan.read);
    const auto& dims = reader->header().dims;
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(int(dims[0]) - 1, int(dims[1]) - 1, int(dims[2]) - 1));
    openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box);  // x fastest, like our slices
    reader->read_slices(dims[2], dense.data());
    const double read_seconds = seconds_since(start);
    float minimum = dense.data()[0];
    for (std::size_t i = 0; i < dense.valueCount(); ++i) minimum = std::min(minimum, dense.data()[i]);
    start = Clock::now();
    auto grid = openvdb::FloatGrid::create(minimum);
    openvdb::tools::copyFromDense(dense, *grid, 0.0f);
    const double copy_seconds = seconds_since(start);
    const double cpu_seconds = cpu_seconds_since(cpu_start);
    const double peak_mb = peak_rss_mb();
    return {{"read_seconds", read_seconds},
            {"copy_seconds", copy_seconds},
            {"cpu_seconds", cpu_seconds},
            {"peak_mb", peak_mb},
            {"grid", grid_figures(*grid, scratch / "dense.vdb")}};
}

std::string fixed(double value, int digits) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(digits) << value;
    return text.str();
}

/// A grid_figures() result as one phrase.
std::string grid_text(const Json& g) {
    return "grid: " + fixed(g["active_voxels"].get<double>() / 1e6, 2) + " M active voxels, " +
           std::to_string(g["leaves"].get<std::size_t>()) + " leaves, " + fixed(g["grid_mb"].get<double>(), 1) +
           " MB in memory, write_vdb " + fixed(g["write_seconds"].get<double>(), 2) + " s, " +
           fixed(g["vdb_mb"].get<double>(), 1) + " MB on disk";
}

/// A mesher's phases as "octree 0.41, coarse 0.05, split 0.02, contour 0.10, weld 0.03": where its time goes.
std::string phases_text(const Json& mesher) {
    std::string text;
    for (const Json& phase : mesher["phases"]) {
        text += (text.empty() ? "" : ", ") + phase[0].get<std::string>() + " " + fixed(phase[1].get<double>(), 3);
    }
    return text;
}

/// The volumeToMesh setting a DC setting is timed against: same position in the lists.
std::size_t matching_openvdb(const std::vector<Setting>& settings, std::size_t adaptive_index) {
    std::size_t first_openvdb = 0;
    while (first_openvdb < settings.size() && settings[first_openvdb].method != MeshMethod::openvdb) ++first_openvdb;
    const auto count = std::size_t(std::count_if(settings.begin(), settings.end(), [](const Setting& s) { return s.method == MeshMethod::openvdb; }));
    return first_openvdb + std::min(adaptive_index, count - 1);
}

/// --budgets: each budget row against its volumeToMesh mesh (from run @a r).
void budget_table(const std::vector<Setting>& settings, const Json& r) {
    bool header = false;
    for (std::size_t i = 0; i < settings.size(); ++i) {
        if (settings[i].budget_route == 0) continue;
        if (!header) {
            std::cout << "\n| budget | triangles | Hausdorff (voxels) | angles < 10 deg | clean | time / volumeToMesh |\n|---|---|---|---|---|---|\n";
            header = true;
        }
        const Json &ours = r["meshes"][i], &theirs = r["meshes"][settings[i].budget_of];
        const auto pair = [&](const char* key, int digits, double scale) {
            return fixed(scale * ours["accuracy"][key].get<double>(), digits) + " / " + fixed(scale * theirs["accuracy"][key].get<double>(), digits);
        };
        std::cout << "| " << settings[i].label() << " | " << ours["triangles"].get<std::size_t>() << " / " << theirs["triangles"].get<std::size_t>()
                  << " | " << pair("hausdorff", 3, 1) << " | " << pair("small_angle_share", 2, 100) << "% | "
                  << (ours["accuracy"]["clean"].get<bool>() ? "yes" : "no") << " / " << (theirs["accuracy"]["clean"].get<bool>() ? "yes" : "no")
                  << " | " << fixed(ours["seconds"].get<double>() / theirs["seconds"].get<double>(), 2) << " |\n";
    }
}

void report(const Scan& scan, const std::vector<Setting>& settings, const std::map<int, Json>& runs, const Json& dense) {
    const int most = runs.rbegin()->first;
    const Json& r = runs.at(most);
    std::cout << "\n## " << scan.name << " (iso " << scan.iso << ")\n\n";
    if (r.contains("failed")) {
        std::cout << "failed: " << r["failed"].get<std::string>() << "\n";
        return;
    }
    const double active_m = r["active_voxels"].get<double>() / 1e6;
    const double convert_s = r["convert_seconds"].get<double>();
    std::cout << "conversion, " << most << " threads: convert_to_grid " << fixed(convert_s, 2) << " s, "
              << fixed(active_m, 2) << " M active voxels (" << fixed(active_m / convert_s, 2)
              << " M/s), " << fixed(r["convert_cpu_seconds"].get<double>(), 2) << " s CPU, peak "
              << fixed(r["convert_peak_mb"].get<double>(), 0) << " MB; " << grid_text(r["grid"]) << "\n";
    if (!dense.contains("failed")) {
        const double dense_s = dense["read_seconds"].get<double>() + dense["copy_seconds"].get<double>();
        std::cout << "dense route: read " << fixed(dense["read_seconds"].get<double>(), 2) << " s + copyFromDense "
                  << fixed(dense["copy_seconds"].get<double>(), 2) << " s, "
                  << fixed(dense["cpu_seconds"].get<double>(), 2) << " s CPU, peak "
                  << fixed(dense["peak_mb"].get<double>(), 0) << " MB; convert_to_grid / dense route = "
                  << fixed(convert_s / dense_s, 2) << "; " << grid_text(dense["grid"]) << "\n";
    }
    std::cout << "\n| mesher | seconds | / volumeToMesh | M triangles/s | triangles | peak MB | phases (s) |";
    for (const auto& [threads, run] : runs)
        if (threads != most) std::cout << " " << threads << "-thread / " << most << "-thread |";
    std::cout << "\n|---|---|---|---|---|---|---|";
    for (std::size_t i = 1; i < runs.size(); ++i) std::cout << "---|";
    std::cout << "\n";
    std::size_t adaptive_index = 0;  // DC settings, in their order
    for (std::size_t i = 0; i < settings.size(); ++i) {
        const Json& m = r["meshes"][i];
        const double s = m["seconds"].get<double>(), triangles = m["triangles"].get<double>();
        std::string ratio = "";
        if (settings[i].budget_route != 0) {
            ratio = fixed(s / r["meshes"][settings[i].budget_of]["seconds"].get<double>(), 2) + " (vs " + settings[settings[i].budget_of].label() + ")";
        } else if (settings[i].method == MeshMethod::dc) {
            const std::size_t j = matching_openvdb(settings, adaptive_index++);
            ratio = fixed(s / r["meshes"][j]["seconds"].get<double>(), 2) + " (vs " + settings[j].label() + ")";
        } else if (settings[i].method == MeshMethod::mc) {
            ratio = fixed(s / r["meshes"][matching_openvdb(settings, 0)]["seconds"].get<double>(), 2);
        }
        std::cout << "| " << settings[i].label() << " | " << fixed(s, 3) << " | " << ratio << " | "
                  << fixed(triangles / 1e6 / s, 2) << " | " << std::size_t(triangles) << " | "
                  << fixed(m["peak_mb"].get<double>(), 0) << " | " << phases_text(m) << " |";
        for (const auto& [threads, run] : runs)
            if (threads != most && !run.contains("failed"))
                std::cout << " " << fixed(run["meshes"][i]["seconds"].get<double>() / s, 2) << " |";
        std::cout << "\n";
    }
    budget_table(settings, r);
    for (const auto& [threads, run] : runs)
        if (threads != most && !run.contains("failed"))
            std::cout << "\nconversion " << threads << "-thread / " << most << "-thread: "
                      << fixed(run["convert_seconds"].get<double>() / convert_s, 2) << "\n";
}

std::vector<double> numbers(const std::string& text) {
    std::vector<double> values;
    std::stringstream in(text);
    for (std::string piece; std::getline(in, piece, ',');) values.push_back(std::stod(piece));
    return values;
}

std::vector<Scan> real_scans(const std::filesystem::path& data, const std::string& wanted) {
    std::vector<Scan> all;
    {
        Scan s{"bunny", data / "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part1of2.raw.gz", {}, 1200.5};
        s.read.raw_dims = std::array<std::int64_t, 3>{512, 512, 361};
        // 12-bit data in 16 bits; the padding outside the field of view, 0xF830, is -2000 only as int16.
        s.read.raw_type = SampleType::i16;
        s.read.raw_byte_order = ByteOrder::big;
        s.read.raw_more_files = {data / "raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part2of2.raw.gz"};
        all.push_back(s);
    }
    {
        Scan s{"cthead", data / "raw_stanford_cthead/CThead_256x256x113_int16be.raw.gz", {}, 600.5};
        s.read.raw_dims = std::array<std::int64_t, 3>{256, 256, 113};
        s.read.raw_type = SampleType::i16;
        s.read.raw_byte_order = ByteOrder::big;
        all.push_back(s);
    }
    all.push_back({"engine", data / "nifti_engine_ct/engine.nii.gz", {}, 100.5});
    all.push_back({"walnut", data / "openqvis_walnut_ct/walnut.dat", {}, kWalnutIso});
    std::vector<Scan> chosen;
    for (const Scan& s : all)
        if (("," + wanted + ",").find("," + s.name + ",") != std::string::npos) chosen.push_back(s);
    return chosen;
}

/// A sphere phantom of @a size^3 written as u8 NIfTI (density x 255, scale 1/255: iso 0.5),
/// in a child (the phantom filler runs TBB, which must not start in the forking parent).
Scan write_phantom(const std::filesystem::path& folder, std::int64_t size) {
    const std::filesystem::path file = folder / ("sphere" + std::to_string(size) + ".nii");
    const Json written = run_forked([&] {
        const PhantomSpec spec = phantom_preset("sphere", {size, size, size});
        VolumeHeader header;
        header.dims = spec.dims;
        header.type = SampleType::u8;
        header.value_scale = 1.0 / phantom_full_scale(SampleType::u8);
        write_volume(file, header, [&](std::int64_t z, float* slice) { fill_phantom_slice(spec, z, slice); });
        return Json{{"written", true}};
    });
    if (written.contains("failed")) throw std::runtime_error(written["failed"].get<std::string>());
    return {"sphere phantom " + std::to_string(size) + "^3", file, {}, 0.5};
}

int run(int argc, char** argv) {
    std::map<std::string, std::string> flags = {{"--scans", "bunny,cthead,engine,walnut"},
                                                {"--phantom-sizes", "256,512"},
                                                {"--errors", "0,0.1,0.25,1"},
                                                {"--adaptivities", "0,0.1,0.25,1"},
                                                {"--threads", "1,2"},
                                                {"--budgets", ""}};
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!flags.count(argv[i])) {
            std::cerr << "unknown flag " << argv[i] << " (see the top of bench/bench_main.cpp)\n";
            return 2;
        }
        flags[argv[i]] = argv[i + 1];
    }
    std::vector<Setting> settings;
    for (double e : numbers(flags["--errors"])) settings.push_back({MeshMethod::dc, e});
    settings.push_back({MeshMethod::mc, 0});
    for (double a : numbers(flags["--adaptivities"])) settings.push_back({MeshMethod::openvdb, a});
    for (std::size_t i = 0, count = settings.size(); i < count; ++i) {
        if (settings[i].method != MeshMethod::openvdb) continue;
        for (double route : numbers(flags["--budgets"])) settings.push_back({MeshMethod::dc, settings[i].value, int(route), i});
    }

    const std::filesystem::path data = test::shared_data_dir();
    std::vector<Scan> scans;
    if (!data.empty()) scans = real_scans(data, flags["--scans"]);
    else std::cerr << "shared data folder not found: real scans skipped\n";
    const std::filesystem::path folder =
        std::filesystem::temp_directory_path() / ("vdbmesh-bench-" + std::to_string(getpid()));
    std::filesystem::create_directories(folder);
    for (double size : numbers(flags["--phantom-sizes"]))
        if (size > 0) scans.push_back(write_phantom(folder, std::int64_t(size)));

    std::cout << "# vdbmesh_bench: " << std::thread::hardware_concurrency() << " hardware threads\n";
    for (const Scan& scan : scans) {
        std::cerr << "bench: " << scan.name << "\n";
        std::map<int, Json> runs;
        for (double threads : numbers(flags["--threads"]))
            runs[int(threads)] = run_forked([&] { return convert_and_mesh(scan, settings, int(threads), folder); });
        const Json dense = run_forked([&] { return dense_route(scan, runs.rbegin()->first, folder); });
        report(scan, settings, runs, dense);
        std::cout << std::flush;
    }
    std::filesystem::remove_all(folder);
    return 0;
}

}  // namespace
}  // namespace vdbmesh::bench

int main(int argc, char** argv) { return vdbmesh::bench::run(argc, argv); }
