// Point clouds in: .xyz/.pts lines, PLY (ASCII, binary little and big endian) and Stanford
// .conf range-scan sets.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

#include "vdbmesh/error.h"
#include "vdbmesh/parse_util.h"
#include "vdbmesh/points.h"

namespace vdbmesh {

namespace {

using detail::parse_double;
using detail::split_words;
using detail::to_lower;
using detail::trim;

std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FormatError(path.string(), "cannot open the file");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void check_normal(const std::filesystem::path& path, const std::string& where, Vec3d& n) {
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 1e-12)) throw FormatError(path.string(), where, "a non-zero normal", "a zero normal");
    for (double& c : n) c /= len;
}

PointCloud read_xyz(const std::filesystem::path& path) {
    const std::string text = read_all(path);
    PointCloud cloud;
    std::size_t pos = 0, line_no = 0;
    int columns = -1;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++line_no;
        const std::size_t hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        line = trim(line);
        if (line.empty()) continue;
        const std::vector<std::string> words = split_words(line, true);
        const std::string where = "line " + std::to_string(line_no);
        if (words.size() != 3 && words.size() != 6)
            throw FormatError(path.string(), where, "3 numbers (x y z) or 6 (x y z nx ny nz)",
                              std::to_string(words.size()) + " fields");
        if (columns < 0) columns = int(words.size());
        if (int(words.size()) != columns)
            throw FormatError(path.string(), where, std::to_string(columns) + " fields like the lines before",
                              std::to_string(words.size()));
        Vec3d p;
        for (int i = 0; i < 3; ++i) p[i] = parse_double(path, where + " field " + std::to_string(i + 1), words[i]);
        cloud.points.push_back(p);
        if (columns == 6) {
            Vec3d n;
            for (int i = 0; i < 3; ++i) n[i] = parse_double(path, where + " field " + std::to_string(i + 4), words[i + 3]);
            check_normal(path, where + " normal", n);
            cloud.normals.push_back(n);
        }
    }
    if (cloud.points.empty()) throw FormatError(path.string(), "points", "at least one point", "none");
    return cloud;
}

// ---- PLY ----

struct PlyProperty {
    std::string name;
    std::string type;        // scalar type, or the item type of a list
    std::string count_type;  // non-empty for lists
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

int type_size(const std::filesystem::path& path, const std::string& type) {
    static const std::pair<const char*, int> sizes[] = {
        {"char", 1},  {"int8", 1},   {"uchar", 1},  {"uint8", 1},   {"short", 2},   {"int16", 2},
        {"ushort", 2}, {"uint16", 2}, {"int", 4},   {"int32", 4},   {"uint", 4},    {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (const auto& [name, size] : sizes)
        if (type == name) return size;
    throw FormatError(path.string(), "property type", "a PLY scalar type (char, uchar, short, ..., float, double)", "\"" + type + "\"");
}

double read_binary(const unsigned char* data, const std::string& type, bool big_endian) {
    unsigned char b[8];
    const int n = (type == "double" || type == "float64") ? 8
                  : (type == "float" || type == "float32" || type == "int" || type == "int32" || type == "uint" || type == "uint32") ? 4
                  : (type == "short" || type == "int16" || type == "ushort" || type == "uint16") ? 2
                                                                                                  : 1;
    for (int i = 0; i < n; ++i) b[i] = data[big_endian ? n - 1 - i : i];
    if (type == "double" || type == "float64") { double v; std::memcpy(&v, b, 8); return v; }
    if (type == "float" || type == "float32") { float v; std::memcpy(&v, b, 4); return v; }
    if (type == "int" || type == "int32") { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    if (type == "uint" || type == "uint32") { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    if (type == "short" || type == "int16") { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    if (type == "ushort" || type == "uint16") { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    if (type == "char" || type == "int8") return double(std::int8_t(b[0]));
    return double(b[0]);
}

PointCloud read_ply(const std::filesystem::path& path) {
    const std::string data = read_all(path);
    const std::string file = path.string();
    if (data.compare(0, 3, "ply") != 0) throw FormatError(file, "magic", "\"ply\"", "\"" + data.substr(0, 3) + "\"");
    // Header
    std::size_t pos = 0, line_no = 0;
    std::string format;
    std::vector<PlyElement> elements;
    bool ended = false;
    while (pos < data.size()) {
        std::size_t end = data.find('\n', pos);
        if (end == std::string::npos) throw FormatError(file, "header", "a line end_header", "the end of the file");
        const std::string line(trim(std::string_view(data.data() + pos, end - pos)));
        pos = end + 1;
        ++line_no;
        const std::vector<std::string> w = split_words(line);
        const std::string where = "header line " + std::to_string(line_no);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info" || w[0] == "ply") continue;
        if (w[0] == "end_header") { ended = true; break; }
        if (w[0] == "format") {
            if (w.size() < 2) throw FormatError(file, where, "format ascii|binary_little_endian|binary_big_endian 1.0", line);
            format = w[1];
            if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
                throw FormatError(file, where, "ascii, binary_little_endian or binary_big_endian", "\"" + format + "\"");
        } else if (w[0] == "element") {
            if (w.size() != 3) throw FormatError(file, where, "element NAME COUNT", "\"" + line + "\"");
            PlyElement e;
            e.name = w[1];
            const std::int64_t count = detail::parse_int(path, where + " element count", w[2]);
            if (count < 0) throw FormatError(file, where + " element count", "a count >= 0", w[2]);
            e.count = std::uint64_t(count);
            elements.push_back(e);
        } else if (w[0] == "property") {
            if (elements.empty()) throw FormatError(file, where, "an element before its properties", "\"" + line + "\"");
            PlyProperty p;
            if (w.size() == 5 && w[1] == "list") {
                p.count_type = w[2];
                p.type = w[3];
                p.name = w[4];
                type_size(path, p.count_type);
            } else if (w.size() == 3) {
                p.type = w[1];
                p.name = w[2];
            } else {
                throw FormatError(file, where, "property TYPE NAME or property list COUNT_TYPE TYPE NAME", "\"" + line + "\"");
            }
            type_size(path, p.type);
            elements.back().properties.push_back(p);
        } else {
            throw FormatError(file, where, "a PLY header keyword", "\"" + w[0] + "\"");
        }
    }
    if (!ended) throw FormatError(file, "header", "a line end_header", "the end of the file");
    if (format.empty()) throw FormatError(file, "header", "a format line", "none");
    const auto vertex = std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
    if (vertex == elements.end()) throw FormatError(file, "header", "an element vertex", "none");
    int index[6] = {-1, -1, -1, -1, -1, -1};
    const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
    for (std::size_t i = 0; i < vertex->properties.size(); ++i)
        for (int k = 0; k < 6; ++k)
            if (vertex->properties[i].name == names[k] && vertex->properties[i].count_type.empty()) index[k] = int(i);
    for (int k = 0; k < 3; ++k)
        if (index[k] < 0) throw FormatError(file, "element vertex", std::string("a property ") + names[k], "none");
    const bool normals = index[3] >= 0 && index[4] >= 0 && index[5] >= 0;
    PointCloud cloud;
    cloud.points.resize(vertex->count);
    if (normals) cloud.normals.resize(vertex->count);
    double values[6] = {0, 0, 0, 0, 0, 0};

    if (format == "ascii") {
        std::size_t line = line_no;
        auto next_line = [&]() -> std::vector<std::string> {
            for (;;) {
                if (pos >= data.size()) throw FormatError(file, "line " + std::to_string(line + 1), "more element data", "the end of the file");
                std::size_t end = data.find('\n', pos);
                if (end == std::string::npos) end = data.size();
                std::string_view l = trim(std::string_view(data.data() + pos, end - pos));
                pos = end + 1;
                ++line;
                if (!l.empty()) return split_words(l);
            }
        };
        for (const PlyElement& e : elements) {
            if (&e == &*vertex) break;
            for (std::uint64_t i = 0; i < e.count; ++i) next_line();  // one line per instance
        }
        for (std::uint64_t v = 0; v < vertex->count; ++v) {
            const std::vector<std::string> w = next_line();
            const std::string where = "line " + std::to_string(line) + " (vertex " + std::to_string(v) + ")";
            std::size_t field = 0;
            for (std::size_t i = 0; i < vertex->properties.size(); ++i) {
                const PlyProperty& p = vertex->properties[i];
                if (field >= w.size())
                    throw FormatError(file, where, "a value for property " + p.name, "the end of the line");
                if (!p.count_type.empty()) {
                    const std::int64_t n = detail::parse_int(path, where + " " + p.name + " count", w[field]);
                    field += 1 + std::size_t(std::max<std::int64_t>(n, 0));
                    continue;
                }
                const double value = parse_double(path, where + " " + p.name, w[field++]);
                for (int k = 0; k < 6; ++k)
                    if (index[k] == int(i)) values[k] = value;
            }
            cloud.points[v] = {values[0], values[1], values[2]};
            if (normals) {
                Vec3d n{values[3], values[4], values[5]};
                check_normal(path, where + " normal", n);
                cloud.normals[v] = n;
            }
        }
    } else {
        const bool big = format == "binary_big_endian";
        const unsigned char* base = reinterpret_cast<const unsigned char*>(data.data());
        auto need = [&](std::size_t bytes, const std::string& what) {
            if (pos + bytes > data.size())
                throw FormatError(file, what, std::to_string(bytes) + " more bytes", std::to_string(data.size() - pos));
        };
        auto skip_list = [&](const PlyProperty& p, const std::string& what) {
            need(type_size(path, p.count_type), what);
            const double n = read_binary(base + pos, p.count_type, big);
            pos += type_size(path, p.count_type);
            const std::size_t bytes = std::size_t(std::max(n, 0.0)) * type_size(path, p.type);
            need(bytes, what);
            pos += bytes;
        };
        auto skip_instance = [&](const PlyElement& e, std::uint64_t i) {
            for (const PlyProperty& p : e.properties) {
                const std::string what = "element " + e.name + " " + std::to_string(i) + " property " + p.name;
                if (p.count_type.empty()) {
                    need(type_size(path, p.type), what);
                    pos += type_size(path, p.type);
                } else {
                    skip_list(p, what);
                }
            }
        };
        for (const PlyElement& e : elements) {
            if (&e == &*vertex) break;
            for (std::uint64_t i = 0; i < e.count; ++i) skip_instance(e, i);
        }
        std::vector<int> sizes, offsets;
        bool fixed = true;
        int stride = 0;
        for (const PlyProperty& p : vertex->properties) {
            if (!p.count_type.empty()) fixed = false;
            offsets.push_back(stride);
            sizes.push_back(type_size(path, p.type));
            stride += sizes.back();
        }
        for (std::uint64_t v = 0; v < vertex->count; ++v) {
            const std::size_t start = pos;
            if (fixed) {
                need(std::size_t(stride), "vertex " + std::to_string(v));
                for (int k = 0; k < 6; ++k)
                    if (index[k] >= 0) values[k] = read_binary(base + start + offsets[index[k]], vertex->properties[index[k]].type, big);
                pos += stride;
            } else {
                for (std::size_t i = 0; i < vertex->properties.size(); ++i) {
                    const PlyProperty& p = vertex->properties[i];
                    const std::string what = "vertex " + std::to_string(v) + " property " + p.name;
                    if (!p.count_type.empty()) {
                        skip_list(p, what);
                        continue;
                    }
                    need(type_size(path, p.type), what);
                    const double value = read_binary(base + pos, p.type, big);
                    pos += type_size(path, p.type);
                    for (int k = 0; k < 6; ++k)
                        if (index[k] == int(i)) values[k] = value;
                }
            }
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite(values[k]))
                    throw FormatError(file, "vertex " + std::to_string(v) + " " + names[k], "a finite number", "non-finite");
            cloud.points[v] = {values[0], values[1], values[2]};
            if (normals) {
                Vec3d n{values[3], values[4], values[5]};
                check_normal(path, "vertex " + std::to_string(v) + " normal", n);
                cloud.normals[v] = n;
            }
        }
    }
    if (cloud.points.empty()) throw FormatError(file, "element vertex", "at least one vertex", "0");
    return cloud;
}

// ---- .conf ----

/// A .conf nests at most this deep (the Stanford sets nest none): a bound besides the cycle
/// check, against chains of distinct files.
constexpr std::size_t kMaxConfDepth = 16;

/// The .conf files being read, outermost first: a file by its device and inode (the same file
/// through any link or path), and by its name for messages.
struct ConfChain {
    std::vector<std::pair<dev_t, ino_t>> ids;
    std::vector<std::string> names;
    std::string text(const std::string& last) const {
        std::string t;
        for (const std::string& name : names) t += name + " -> ";
        return t + last;
    }
    void enter(const std::filesystem::path& path) {
        struct stat info {};
        if (::stat(path.c_str(), &info) != 0) throw FormatError(path.string(), "cannot open the file");
        ids.emplace_back(info.st_dev, info.st_ino);
        names.push_back(path.string());
    }
    void leave() {
        ids.pop_back();
        names.pop_back();
    }
};

PointCloud read_points_in(const std::filesystem::path& path, ConfChain& chain);

/// Refuses a `bmesh` line of @a path naming a .conf already being read (a cycle) or one too deep.
void refuse_conf_cycle(const std::filesystem::path& path, const std::string& where, const std::filesystem::path& scan_path,
                       const ConfChain& chain) {
    if (to_lower(scan_path.extension().string()) != ".conf") return;
    struct stat info {};
    if (::stat(scan_path.c_str(), &info) == 0 &&
        std::find(chain.ids.begin(), chain.ids.end(), std::make_pair(info.st_dev, info.st_ino)) != chain.ids.end())
        throw FormatError(path.string(), where + ": bmesh", "a scan file, not a .conf already being read",
                          "a cycle " + chain.text(scan_path.string()));
    if (chain.ids.size() >= kMaxConfDepth)
        throw FormatError(path.string(), where + ": bmesh", ".conf files nested at most " + std::to_string(kMaxConfDepth) + " deep",
                          "a deeper chain " + chain.text(scan_path.string()));
}

/// One `bmesh FILE tx ty tz qx qy qz qw` line of a .conf.
struct ConfEntry {
    std::string where;           ///< "line N"
    std::filesystem::path scan;  ///< a relative FILE taken from the .conf's folder
    double pose[7];              ///< tx ty tz qx qy qz qw, the quaternion not zero
};

/// The `bmesh` lines of the .conf @a path (`camera` lines and comments skipped).
std::vector<ConfEntry> parse_conf(const std::filesystem::path& path) {
    const std::string text = read_all(path);
    std::vector<ConfEntry> entries;
    std::istringstream in(text);
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        const std::vector<std::string> w = split_words(trim(line));
        if (w.empty() || w[0][0] == '#' || w[0] == "camera") continue;
        ConfEntry entry;
        entry.where = "line " + std::to_string(line_no);
        if (w[0] != "bmesh") throw FormatError(path.string(), entry.where, "bmesh FILE tx ty tz qx qy qz qw (or camera ...)", "\"" + w[0] + "\"");
        if (w.size() != 9) throw FormatError(path.string(), entry.where, "9 fields (bmesh FILE tx ty tz qx qy qz qw)", std::to_string(w.size()));
        const char* fields[7] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
        for (int i = 0; i < 7; ++i) entry.pose[i] = parse_double(path, entry.where + " " + fields[i], w[2 + i]);
        const double* q = entry.pose + 3;
        if (!(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) > 1e-9))
            throw FormatError(path.string(), entry.where + " quaternion", "a non-zero quaternion", "0 0 0 0");
        entry.scan = w[1];
        if (entry.scan.is_relative()) entry.scan = path.parent_path() / entry.scan;
        entries.push_back(std::move(entry));
    }
    return entries;
}

PointCloud read_conf(const std::filesystem::path& path, ConfChain& chain) {
    chain.enter(path);
    PointCloud cloud;
    for (const ConfEntry& entry : parse_conf(path)) {
        double qx = entry.pose[3], qy = entry.pose[4], qz = entry.pose[5], qw = entry.pose[6];
        const double len = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
        // The inverse (conjugate) rotation: checked against bun_zipper.ply.
        qx = -qx / len, qy = -qy / len, qz = -qz / len, qw /= len;
        const double R[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
                                {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
                                {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
        refuse_conf_cycle(path, entry.where, entry.scan, chain);
        PointCloud scan;
        try {
            scan = read_points_in(entry.scan, chain);
        } catch (const FormatError& e) {
            throw FormatError(path.string(), entry.where + ": " + e.what());
        }
        const auto index = std::uint32_t(cloud.scan_view.size());
        cloud.scan_view.push_back({R[0][2], R[1][2], R[2][2]});
        const bool normals = scan.has_normals() && (cloud.points.empty() || cloud.has_normals());
        if (!normals) cloud.normals.clear();
        for (std::size_t i = 0; i < scan.points.size(); ++i) {
            const Vec3d& p = scan.points[i];
            Vec3d q;
            for (int r = 0; r < 3; ++r) q[r] = R[r][0] * p[0] + R[r][1] * p[1] + R[r][2] * p[2] + entry.pose[r];
            cloud.points.push_back(q);
            cloud.scan.push_back(index);
            if (normals) {
                const Vec3d& n = scan.normals[i];
                Vec3d m;
                for (int r = 0; r < 3; ++r) m[r] = R[r][0] * n[0] + R[r][1] * n[1] + R[r][2] * n[2];
                cloud.normals.push_back(m);
            }
        }
    }
    if (cloud.points.empty()) throw FormatError(path.string(), "bmesh lines", "at least one scan with points", "none");
    chain.leave();
    return cloud;
}

/// Appends the files the .conf @a path names to @a files, a nested .conf's after it.
void list_conf(const std::filesystem::path& path, ConfChain& chain, std::vector<std::filesystem::path>& files) {
    chain.enter(path);
    for (const ConfEntry& entry : parse_conf(path)) {
        refuse_conf_cycle(path, entry.where, entry.scan, chain);
        files.push_back(entry.scan);
        if (to_lower(entry.scan.extension().string()) == ".conf" && std::filesystem::exists(entry.scan))
            list_conf(entry.scan, chain, files);
    }
    chain.leave();
}

PointCloud read_points_in(const std::filesystem::path& path, ConfChain& chain) {
    if (!std::filesystem::exists(path)) throw FormatError(path.string(), "the file does not exist");
    const std::string ext = to_lower(path.extension().string());
    if (ext == ".ply") return read_ply(path);
    if (ext == ".conf") return read_conf(path, chain);
    if (ext == ".xyz" || ext == ".pts" || ext == ".txt" || ext == ".xyzn") return read_xyz(path);
    throw FormatError(path.string(), "extension", ".xyz, .pts, .txt, .ply or .conf", "\"" + ext + "\"");
}

}  // namespace

PointCloud read_points(const std::filesystem::path& path) {
    ConfChain chain;
    return read_points_in(path, chain);
}

std::vector<std::filesystem::path> conf_scan_files(const std::filesystem::path& conf) {
    ConfChain chain;
    std::vector<std::filesystem::path> files;
    list_conf(conf, chain, files);
    return files;
}

void write_points_xyz(const PointCloud& cloud, const std::filesystem::path& path) {
    std::ofstream out(path);
    if (!out) throw Error("cannot write " + path.string());
    out.precision(9);
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const Vec3d& p = cloud.points[i];
        out << p[0] << ' ' << p[1] << ' ' << p[2];
        if (cloud.has_normals()) out << ' ' << cloud.normals[i][0] << ' ' << cloud.normals[i][1] << ' ' << cloud.normals[i][2];
        out << '\n';
    }
    if (!out) throw Error("cannot write " + path.string());
}

}  // namespace vdbmesh
