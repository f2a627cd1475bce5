#include "common_options.h"

#include <tbb/global_control.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <iostream>

#include "option_checks.h"
#include "work_limits.h"
#include "vdbmesh/error.h"

namespace vdbmesh::cli {

void add_common_options(CLI::App& command, CommonOptions& options) {
    command.add_option("--threads", options.threads, "Worker threads (0: all cores); output is the same for any count")
        ->check(CLI::Range(0, kMaxThreads));
    command.add_flag("-q,--quiet", options.quiet, "No progress output");
}

ThreadLimit::ThreadLimit(const CommonOptions& options) {
    if (options.threads > 0)
        control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<std::size_t>(options.threads));
}
ThreadLimit::~ThreadLimit() = default;

std::vector<double> parse_number_list(const std::string& flag, const std::string& text) {
    std::vector<double> values;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string piece = text.substr(start, comma - start);
        double value = 0;
        const auto [end, ec] = std::from_chars(piece.data(), piece.data() + piece.size(), value);
        if (piece.empty() || ec != std::errc() || end != piece.data() + piece.size() || !std::isfinite(value))
            throw UsageError(flag + ": expected comma-separated numbers, got \"" + text + "\"");
        values.push_back(value);
        start = comma + 1;
    }
    return values;
}

std::uint64_t parse_memory_size(const std::string& flag, const std::string& text) {
    const auto fail = [&] { return UsageError(flag + ": expected a size such as 512M or 4G (K, M, G: powers of 1024), at least 1M, got \"" + text + "\""); };
    std::uint64_t number = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
    if (ec != std::errc() || end == text.data()) throw fail();
    const std::string suffix(end, text.data() + text.size());
    int shift = 0;
    if (suffix == "K" || suffix == "k") shift = 10;
    else if (suffix == "M" || suffix == "m") shift = 20;
    else if (suffix == "G" || suffix == "g") shift = 30;
    else if (!suffix.empty()) throw fail();
    if (number > (~std::uint64_t(0) >> shift) || (number << shift) < (std::uint64_t(1) << 20)) throw fail();
    return number << shift;
}

ReadOptions ReadFlags::to_read_options(const std::vector<std::string>& more_inputs) const {
    ReadOptions options;
    if (!more_inputs.empty() && raw_dims.empty())
        throw UsageError("more than one input is only for a raw scan split over several files, which needs --raw-dims X,Y,Z");
    for (const CLI::Option* option : raw_only) {
        if (raw_dims.empty() && option->count() > 0)
            throw UsageError(option->get_name() + ": only for headerless raw input, which needs --raw-dims X,Y,Z (the file's own header gives it otherwise)");
    }
    options.raw_more_files.assign(more_inputs.begin(), more_inputs.end());
    if (!raw_dims.empty()) {
        const auto dims = parse_number_list("--raw-dims", raw_dims);
        if (dims.size() != 3) throw UsageError("--raw-dims: expected X,Y,Z, got \"" + raw_dims + "\"");
        std::array<std::int64_t, 3> whole{};
        for (int i = 0; i < 3; ++i) {
            if (dims[i] < 1 || dims[i] != std::floor(dims[i]) || dims[i] > 9.0e15)
                throw UsageError("--raw-dims: expected positive whole numbers, got \"" + raw_dims + "\"");
            whole[i] = static_cast<std::int64_t>(dims[i]);
        }
        options.raw_dims = whole;
    }
    options.raw_type = parse_sample_type(raw_type);
    if (raw_endian != "little" && raw_endian != "big")
        throw UsageError("--raw-endian: expected little or big, got \"" + raw_endian + "\"");
    options.raw_byte_order = raw_endian == "little" ? ByteOrder::little : ByteOrder::big;
    if (!spacing.empty()) {
        const auto s = parse_number_list("--spacing", spacing);
        if (s.size() != 3 || s[0] <= 0 || s[1] <= 0 || s[2] <= 0)
            throw UsageError("--spacing: expected three positive numbers SX,SY,SZ, got \"" + spacing + "\"");
        options.raw_spacing = {s[0], s[1], s[2]};
    }
    if (header_bytes < 0) throw UsageError("--header-bytes: expected a number of bytes >= 0, got " + std::to_string(header_bytes));
    options.raw_header_bytes = std::uint64_t(header_bytes);
    options.allow_outside_data = allow_outside_data;
    return options;
}

void add_read_flags(CLI::App& command, ReadFlags& flags) {
    auto* group = command.add_option_group("Headerless raw input");
    const CLI::Option* dims = group->add_option("--raw-dims", flags.raw_dims, "Read INPUT as headerless raw with these dims X,Y,Z");
    flags.raw_only = {
        group->add_option("--raw-type", flags.raw_type, "Sample type: u8|i8|u16|i16|u32|i32|f32|f64")->capture_default_str(),
        group->add_option("--raw-endian", flags.raw_endian, "Byte order: little|big")->capture_default_str(),
        group->add_option("--spacing", flags.spacing, "Voxel spacing SX,SY,SZ (world units)"),
        group->add_option("--header-bytes", flags.header_bytes, "Bytes to skip before the samples"),
    };
    const CLI::Option* outside = command.add_flag("--allow-outside-data", flags.allow_outside_data,
                                                  "Read a data file that a MetaImage, NRRD or OpenQVis header names outside its own folder");
    flags.scan_only = flags.raw_only;
    flags.scan_only.insert(flags.scan_only.begin(), dims);
    flags.scan_only.push_back(outside);
}

void ReadFlags::refuse_for_mesh(const std::string& mesh) const {
    for (const CLI::Option* option : scan_only) refuse_unless(option, false, "for a scan input, got the mesh " + mesh);
}

Progress::Progress(std::string label, bool quiet) : label_(std::move(label)), enabled_(!quiet && ::isatty(2)) {}

Progress::~Progress() {
    if (enabled_ && last_percent_ >= 0) std::cerr << "\r" << std::string(label_.size() + 8, ' ') << "\r" << std::flush;
}

void Progress::operator()(double fraction) {
    if (!enabled_) return;
    const int percent = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 100));
    if (percent == last_percent_) return;
    last_percent_ = percent;
    std::cerr << "\r" << label_ << " " << percent << "%" << std::flush;
}

}  // namespace vdbmesh::cli
