// runtime/brick_output.cpp — the .vti and .vdb brick writers (brick_output.hpp).
#include "runtime/brick_output.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/brick_files.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"
#include "runtime/vdb.hpp"
#include "runtime/vti.hpp"
#include "runtime/vtkhdf.hpp"
#include "runtime/volume_order.hpp"

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

/// A .pvti's pieces: slabs of whole layers of bricks along Z, as even as the layers allow;
/// each piece but the last also holds the next slab's first slice (the shared plane).
struct Slab {
    int first = 0, last = 0;   ///< slices, inclusive
};

std::vector<Slab> piece_slabs(const BrickLayout& layout, int pieces) {
    const int layers = layout.counts[2], slices = layout.grid.slices();
    pieces = std::clamp(pieces, 1, layers);
    std::vector<Slab> slabs;
    for (int p = 0; p < pieces; ++p) {
        const int first_layer = int(std::int64_t(layers) * p / pieces);
        const int next_layer = int(std::int64_t(layers) * (p + 1) / pieces);
        slabs.push_back({first_layer * layout.shape[2], std::min(next_layer * layout.shape[2], slices - 1)});
    }
    return slabs;
}

/// `NAME_P.vti` beside `NAME.pvti`.
std::string piece_path(const std::string& destination, int piece) {
    const std::filesystem::path p(destination);
    return (p.parent_path() / fmt::format("{}_{}.vti", p.stem().string(), piece)).string();
}

/// The .vti (one piece over all slices) or the .pvti's pieces: each a header, the array's
/// length, the values at their offsets, the trailer.
class VtiBricks final : public BrickOutput {
public:
    explicit VtiBricks(const BrickOutputSpec& spec) : spec_(spec) {
        const Grid& g = spec.layout.grid;
        const bool split = has_extension(spec.path, ".pvti");
        const std::vector<Slab> slabs = split ? piece_slabs(spec.layout, spec.pieces) : std::vector<Slab>{{0, g.slices() - 1}};
        for (std::size_t p = 0; p < slabs.size(); ++p) {
            const std::string destination = split ? piece_path(spec.path, int(p)) : spec.path;
            pieces_.push_back(std::make_unique<Piece>(slabs[p], destination, !spec.create));
            Piece& piece = *pieces_.back();
            const std::string header = split ? vti_piece_header(g, slabs[p].first, slabs[p].last, spec.mimages)
                                             : vti_header(g, spec.mimages);
            const std::uint64_t bytes = 8 * std::uint64_t(g.cols()) * g.rows() * (slabs[p].last - slabs[p].first + 1);
            piece.data = header.size() + 8;
            piece.array_stride = 8 + bytes;
            if (spec.create) {
                piece.file.write_at(0, header.data(), header.size());
                // Each array after its length: the value, then the components n1...
                for (int a = 0; a < arrays(); ++a) piece.file.write_at(header.size() + a * piece.array_stride, &bytes, 8);
                const std::string_view trailer = vti_trailer();
                piece.file.write_at(header.size() + arrays() * piece.array_stride, trailer.data(), trailer.size());
            }
        }
    }

    void write(std::size_t, const BrickBox& box, const std::vector<double>& values,
               std::span<const double> components) override {
        write_array(box, 0, values.data());
        for (int k = 1; k < arrays(); ++k) write_array(box, k, components.data() + (k - 1) * box.points());
    }

    void sync() override {
        for (const auto& piece : pieces_) piece->file.sync();
    }

    void finish(std::size_t) override {
        for (const auto& piece : pieces_) piece->file.commit();
        if (has_extension(spec_.path, ".pvti")) write_index();
    }

private:
    struct Piece {
        Piece(Slab s, const std::string& destination, bool keep)
            : slab(s), file(partial_path(destination), destination, keep) {}
        Slab slab;
        PartialFile file;
        std::uint64_t data = 0;           ///< where the value array's numbers start
        std::uint64_t array_stride = 0;   ///< from one array's numbers to the next's
    };

    /// The value, and the components with M-images.
    int arrays() const { return 1 + (spec_.mimages ? fv_component_count(spec_.layout.grid) : 0); }

    /// One array's part of a brick (BrickBox::local order) to its offsets in every piece.
    void write_array(const BrickBox& box, int array, const double* values) {
        const Grid& g = spec_.layout.grid;
        const std::array<int, 3> e = box.extent();
        std::vector<PartialFile::Piece> rows;
        for (const auto& piece : pieces_)
            for (int s = std::max(box.lo[2], piece->slab.first); s <= std::min(box.hi[2], piece->slab.last); ++s) {
                // Volume order: Y from the smallest, so image row r is volume row rows-1-r.
                auto offset = [&](int r) {
                    return piece->data + array * piece->array_stride +
                           8 * ((std::uint64_t(s - piece->slab.first) * g.rows() + (g.rows() - 1 - r)) * g.cols() + box.lo[0]);
                };
                if (e[0] == g.cols()) {   // whole rows: the slice's part is one run, rows in reverse
                    rows.clear();
                    for (int r = box.hi[1]; r >= box.lo[1]; --r)
                        rows.push_back({values + box.local(box.lo[0], r, s), 8 * std::size_t(e[0])});
                    piece->file.write_at(offset(box.hi[1]), rows);
                } else {
                    for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                        piece->file.write_at(offset(r), values + box.local(box.lo[0], r, s), 8 * std::size_t(e[0]));
                }
            }
    }

    void write_index() const {
        const Grid& g = spec_.layout.grid;
        const std::array<double, 3> o = volume_origin(g), sp = volume_spacing(g);
        std::string text = fmt::format(
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
            "  <PImageData WholeExtent=\"0 {} 0 {} 0 {}\" GhostLevel=\"0\" Origin=\"{:.17g} {:.17g} {:.17g}\" "
            "Spacing=\"{:.17g} {:.17g} {:.17g}\">\n"
            "    <PPointData Scalars=\"value\">\n"
            "      <PDataArray type=\"Float64\" Name=\"value\"/>\n",
            g.cols() - 1, g.rows() - 1, g.slices() - 1, o[0], o[1], o[2], sp[0], sp[1], sp[2]);
        for (int k = 1; k < arrays(); ++k) text += fmt::format("      <PDataArray type=\"Float64\" Name=\"n{}\"/>\n", k);
        text += "    </PPointData>\n";
        for (std::size_t p = 0; p < pieces_.size(); ++p)
            text += fmt::format("    <Piece Extent=\"0 {} 0 {} {} {}\" Source=\"{}\"/>\n", g.cols() - 1, g.rows() - 1,
                                pieces_[p]->slab.first, pieces_[p]->slab.last,
                                std::filesystem::path(piece_path(spec_.path, int(p))).filename().string());
        text += "  </PImageData>\n</VTKFile>\n";
        write_file_atomically(spec_.path, [&](OutputFile& out) { out.write(text); });
    }

    BrickOutputSpec spec_;
    std::vector<std::unique_ptr<Piece>> pieces_;
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
        : spec_(spec), band_(vdb_band_width(spec.layout.grid, spec.vdb_band)),
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

    void write(std::size_t index, const BrickBox& box, const std::vector<double>& values,
               std::span<const double>) override {
        const Grid& g = spec_.layout.grid;
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
    }

    void sync() override { file_.sync(); }

    void finish(std::size_t memory_limit) override {
        std::string error;
        const VdbModule* module = vdb_module(error);
        if (!module) throw OutputError(spec_.path, error);
        void* builder = module->begin(spec_.layout.grid, spec_.vdb_band);
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
    return has_extension(path, ".vti") || has_extension(path, ".vdb") || brick_output_only(path);
}

bool brick_output_only(const std::string& path) { return has_extension(path, ".pvti") || brick_output_collective(path); }

bool brick_output_collective(const std::string& path) {
    return has_extension(path, ".hdf") || has_extension(path, ".vtkhdf");
}

bool brick_output_takes_mimages(const std::string& path) {
    return has_extension(path, ".vti") || has_extension(path, ".pvti") || brick_output_collective(path);
}

BrickLayout brick_layout(const std::string& path, const Grid& grid, int edge) {
    if (has_extension(path, ".vdb")) return BrickLayout(grid, edge);
    return BrickLayout::whole_rows(grid, edge);
}

bool brick_partials_exist(const BrickOutputSpec& spec) {
    if (has_extension(spec.path, ".vdb")) return true;   // record files appear as ranks write
    if (has_extension(spec.path, ".vti") || brick_output_collective(spec.path))
        return std::filesystem::exists(partial_path(spec.path));
    const std::size_t pieces = piece_slabs(spec.layout, spec.pieces).size();
    for (std::size_t p = 0; p < pieces; ++p)
        if (!std::filesystem::exists(partial_path(piece_path(spec.path, int(p))))) return false;
    return true;
}

std::unique_ptr<BrickOutput> open_brick_output(const BrickOutputSpec& spec) {
    if (spec.mimages && !brick_output_takes_mimages(spec.path))
        throw OutputError(spec.path, "only .vti, .pvti and .hdf hold the M-images' components");
    if (has_extension(spec.path, ".vti") || has_extension(spec.path, ".pvti")) return std::make_unique<VtiBricks>(spec);
    if (has_extension(spec.path, ".vdb")) return std::make_unique<VdbBricks>(spec);
    if (brick_output_collective(spec.path)) return open_vtkhdf_bricks(spec);
    throw OutputError(spec.path, "only .vti, .pvti, .hdf and .vdb are written brick by brick");
}

void write_field_as_brick(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    const Grid& g = field.grid;
    BrickOutputSpec spec{target.path, BrickLayout(g, std::array<int, 3>{g.cols(), g.rows(), g.slices()}), 3.0, 0, true, 1};
    spec.mimages = options.mimages;
    const std::unique_ptr<BrickOutput> output = open_brick_output(spec);
    const BrickBox whole = spec.layout.box(0);
    if (!options.mimages) {
        output->write(0, whole, field.values, {});
    } else {
        // Slabs of whole slices, so the components take a slab's memory, not five fields'.
        const FvStencil stencil(g);
        const std::size_t slice_points = std::size_t(g.cols()) * g.rows();
        const int slab = int(std::clamp<std::size_t>((std::size_t(1) << 20) / slice_points, 1, g.slices()));
        std::vector<double> values, components;
        for (int first = 0; first < g.slices(); first += slab) {
            const BrickBox part{{0, 0, first}, {g.cols() - 1, g.rows() - 1, std::min(first + slab, g.slices()) - 1}};
            const auto from = field.values.begin() + std::ptrdiff_t(g.index(0, 0, first));
            values.assign(from, from + std::ptrdiff_t(part.points()));
            components.resize(std::size_t(stencil.components()) * part.points());
            double* out[5];
            for (int k = 0; k < stencil.components(); ++k) out[k] = components.data() + k * part.points();
            stencil.box(field.values.data(), whole, part, out);
            output->write(0, part, values, components);
        }
    }
    output->close();
    output->finish(0);
}

}  // namespace fortu
