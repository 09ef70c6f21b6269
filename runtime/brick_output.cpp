// runtime/brick_output.cpp — the .vti and .vdb brick writers (brick_output.hpp).
#include "runtime/brick_output.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/brick_files.hpp"
#include "runtime/output_error.hpp"
#include "runtime/vdb.hpp"
#include "runtime/vti.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <mutex>
#include <set>

namespace fortu {
namespace {

bool has_extension(const std::string& path, const char* ext) {
    return std::filesystem::path(path).extension() == ext;
}

/// The .vti: header, the array's length, the values at their offsets, the trailer.
class VtiBricks final : public BrickOutput {
public:
    explicit VtiBricks(const BrickOutputSpec& spec)
        : spec_(spec), file_(partial_path(spec.path), spec.path, !spec.create) {
        const Grid& g = spec.grid;
        const std::string header = vti_header(g);
        const std::uint64_t bytes = 8 * std::uint64_t(g.points());
        data_ = header.size() + 8;
        if (spec.create) {
            file_.write_at(0, header.data(), header.size());
            file_.write_at(header.size(), &bytes, 8);
            const std::string_view trailer = vti_trailer();
            file_.write_at(data_ + bytes, trailer.data(), trailer.size());
        }
    }

    void write(std::size_t, const BrickBox& box, const std::vector<double>& values) override {
        const Grid& g = spec_.grid;
        const std::array<int, 3> e = box.extent();
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r) {
                // Volume order: Y from the smallest, so image row r is volume row rows-1-r.
                const std::uint64_t at = data_ + 8 * ((std::uint64_t(s) * g.rows() + (g.rows() - 1 - r)) * g.cols() + box.lo[0]);
                file_.write_at(at, values.data() + box.local(box.lo[0], r, s), 8 * std::size_t(e[0]));
            }
        file_.sync();
    }

    void finish(std::size_t) override { file_.commit(); }

private:
    BrickOutputSpec spec_;
    PartialFile file_;
    std::uint64_t data_ = 0;
};

/// One record per brick in the part's file: brick number, voxel count, then per voxel
/// (i, j, k) as int32 and the value as float.
struct RecordHeader {
    std::uint64_t brick;
    std::uint64_t count;
};

class VdbBricks final : public BrickOutput {
public:
    explicit VdbBricks(const BrickOutputSpec& spec)
        : spec_(spec), band_(vdb_band_width(spec.grid, spec.vdb_band)),
          file_(remove_stale_parts(spec), spec.path, !spec.create) {
        if (!spec.create) file_.truncate(complete_records_end(file_.path()));
    }

    /// The record files of every writer of this destination, `.NAME.bricks.r<PART>`.
    std::vector<std::string> parts() const {
        const std::filesystem::path prefix(partial_path(spec_.path, ".r"));
        std::vector<std::string> found;
        std::error_code ec;
        for (const auto& entry : std::filesystem::directory_iterator(
                 prefix.parent_path().empty() ? std::filesystem::path(".") : prefix.parent_path(), ec)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind(prefix.filename().string(), 0) == 0) found.push_back(entry.path().string());
        }
        std::sort(found.begin(), found.end());
        return found;
    }

    std::optional<double> skip_beyond() const override { return band_; }

    void write(std::size_t index, const BrickBox& box, const std::vector<double>& values) override {
        const Grid& g = spec_.grid;
        std::string record(sizeof(RecordHeader), '\0');
        std::uint64_t count = 0;
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c) {
                    const double v = values[box.local(c, r, s)];
                    if (!(std::fabs(v) <= band_)) continue;   // the in-memory writer's test (NaN is out)
                    const std::int32_t ijk[3] = {c, g.rows() - 1 - r, s};
                    const float f = static_cast<float>(v);
                    record.append(reinterpret_cast<const char*>(ijk), sizeof ijk);
                    record.append(reinterpret_cast<const char*>(&f), sizeof f);
                    ++count;
                }
        const RecordHeader h{index, count};
        std::memcpy(record.data(), &h, sizeof h);
        std::lock_guard lock(mutex_);
        file_.append(record.data(), record.size());
        file_.sync();
    }

    void finish(std::size_t memory_limit) override {
        std::string error;
        const VdbModule* module = vdb_module(error);
        if (!module) throw OutputError(spec_.path, error);
        void* builder = module->begin(spec_.grid, spec_.vdb_band);
        if (!builder) throw OutputError(spec_.path, "OpenVDB could not start a grid");
        try {
            std::set<std::uint64_t> seen;   // a brick recomputed after a resume is in twice
            std::vector<std::int32_t> ijk;
            std::vector<float> value;
            for (const std::string& part : parts()) {
                std::ifstream in(part, std::ios::binary);
                RecordHeader h{};
                while (in.read(reinterpret_cast<char*>(&h), sizeof h)) {
                    ijk.resize(3 * h.count);
                    value.resize(h.count);
                    std::string bytes(16 * h.count, '\0');
                    if (!in.read(bytes.data(), std::streamsize(bytes.size()))) break;
                    if (!seen.insert(h.brick).second) continue;
                    for (std::uint64_t n = 0; n < h.count; ++n) {
                        std::memcpy(&ijk[3 * n], bytes.data() + 16 * n, 12);
                        std::memcpy(&value[n], bytes.data() + 16 * n + 12, 4);
                    }
                    module->add(builder, ijk.data(), value.data(), h.count);
                    if (memory_limit && module->memory(builder) > memory_limit)
                        throw OutputError(spec_.path, fmt::format("the sparse grid outgrew --memory ({} MiB held); "
                                                                  "raise --memory or narrow --band",
                                                                  module->memory(builder) >> 20));
                }
            }
        } catch (...) {
            module->discard(builder);
            throw;
        }
        std::string bytes;
        if (std::string e = module->finish(builder, bytes); !e.empty()) throw OutputError(spec_.path, e);
        write_file_atomically(spec_.path, [&](OutputFile& out) { out.write(bytes); });
        for (const std::string& part : parts()) std::filesystem::remove(part);
    }

private:
    /// This writer's record file; a fresh run's first writer first removes those an earlier
    /// run left (perhaps with more ranks).
    static std::string remove_stale_parts(const BrickOutputSpec& spec) {
        const std::string mine = partial_path(spec.path, fmt::format(".r{}", spec.part));
        if (spec.create && spec.part == 0) {
            const std::filesystem::path prefix(partial_path(spec.path, ".r"));
            std::error_code ec;
            const std::filesystem::path dir = prefix.parent_path().empty() ? "." : prefix.parent_path();
            std::vector<std::filesystem::path> stale;
            for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
                if (entry.path().filename().string().rfind(prefix.filename().string(), 0) == 0) stale.push_back(entry.path());
            for (const auto& p : stale) std::filesystem::remove(p, ec);
        }
        return mine;
    }

    /// The end of the last whole record (a kill may leave a torn one after it).
    static std::uint64_t complete_records_end(const std::string& path) {
        const std::uint64_t size = std::filesystem::file_size(path);
        std::ifstream in(path, std::ios::binary);
        std::uint64_t end = 0;
        RecordHeader h{};
        while (end + sizeof h <= size && in.seekg(std::streamoff(end)) && in.read(reinterpret_cast<char*>(&h), sizeof h)) {
            const std::uint64_t next = end + sizeof h + 16 * h.count;
            if (h.count > size || next > size) break;
            end = next;
        }
        return end;
    }

    BrickOutputSpec spec_;
    double band_;
    PartialFile file_;
    std::mutex mutex_;
};

}  // namespace

bool brick_output_supported(const std::string& path) {
    return has_extension(path, ".vti") || has_extension(path, ".vdb");
}

std::unique_ptr<BrickOutput> open_brick_output(const BrickOutputSpec& spec) {
    if (has_extension(spec.path, ".vti")) return std::make_unique<VtiBricks>(spec);
    if (has_extension(spec.path, ".vdb")) return std::make_unique<VdbBricks>(spec);
    throw OutputError(spec.path, "only .vti and .vdb are written brick by brick");
}

}  // namespace fortu
