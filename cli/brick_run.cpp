// cli/brick_run.cpp — the bricked run (brick_run.hpp): plan and memory check, the done map,
// bricks drawn from the shared counter by every thread of every rank, then rank 0 assembles.
#include "cli/brick_run.hpp"

#include "cli/model_setup.hpp"
#include "cli/mpi_world.hpp"
#include "cli/run_checks.hpp"
#include "cli/run_grid.hpp"

#include "interp/brick_fields.hpp"
#include "interp/engine.hpp"
#include "interp/grid_size.hpp"
#include "interp/stage_print.hpp"
#include "runtime/brick_files.hpp"
#include "runtime/brick_output.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"
#include "runtime/parallel.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <functional>
#include <iostream>
#include <mutex>
#include <sys/resource.h>
#include <thread>

namespace fortu {
namespace {

/// Largest grid a bricked run takes: 2^40 points (8 TiB of float64 values).
constexpr double kMaxBrickedPoints = 1099511627776.0;

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

Grid bricked_grid(const Model& model, const CliOptions& o) {
    const std::array<AxisRange, 3> box = run_box(model, o);
    const Grid grid = sized_grid(model, o.size, {box[0], box[1], box[2]});
    if (double(grid.cols()) * grid.rows() * grid.slices() > kMaxBrickedPoints)
        throw UsageError(fmt::format("--size: {} points are more than a bricked run takes (2^40)",
                                     format_count(grid.points())));
    return grid;
}

std::string extension(const std::string& path) { return std::filesystem::path(path).extension().string(); }

/// The file whose name the done map takes: -o, or --mimages when it is the only output.
const std::string& lead_output(const CliOptions& o) { return o.output.empty() ? o.mimages : o.output; }

/// What identifies the values of a run: a done map of another run must not be resumed.
/// Whether the M-images are written is part of it: their files are other partial files.
std::string run_key(const Model& model, const BrickLayout& layout, int pieces, const CliOptions& o,
                    const Engine& engine) {
    const Grid& g = layout.grid;
    const std::size_t model_hash = std::hash<std::string>{}(print_stage(model, "", IrStage::Lower));
    return fmt::format("fortu bricks 2; grid {}x{}x{} x {:.17g}:{:.17g} y {:.17g}:{:.17g} z {:.17g}:{:.17g}; "
                       "brick {}x{}x{}; {}; mimages {}; pieces {}; band {:.17g}; {}; model {:016x}",
                       g.cols(), g.rows(), g.slices(), g.x.min, g.x.max, g.y.min, g.y.max, g.z.min, g.z.max,
                       layout.shape[0], layout.shape[1], layout.shape[2],
                       o.output.empty() ? "none" : extension(o.output), o.mimages.empty() ? "none" : extension(o.mimages),
                       pieces, o.vdb_band, engine.description(), model_hash);
}

struct WorkerStats {
    std::size_t bricks = 0;
    double brick_seconds = 0, max_brick_seconds = 0;
    std::size_t evaluated = 0, skipped = 0;
};

}  // namespace

bool wants_bricks(const Model& model, const CliOptions& o) {
    if (model.dims() != 3 || o.slice || !brick_output_supported(lead_output(o))) return false;
    return o.memory > 0 || o.resume || brick_output_only(o.output) || brick_output_only(o.mimages) ||
           (World::get().distributed() && !o.sweep_point);
}

int run_bricked(const Model& model, const CliOptions& o, double compile_seconds) {
    World& world = World::get();
    if (o.sweep_point && world.distributed())
        throw UsageError("--set under mpirun shares out the sweep's runs; each run is in memory (drop --memory and "
                         "--resume)");
    if (!o.contour.empty() || !o.steps.empty() || o.compare)
        throw UsageError("a bricked run (--memory, --resume, mpirun) writes -o and --mimages only: drop --contour, "
                         "--steps and --compare");
    if (!o.mimages.empty() && !brick_output_takes_mimages(o.mimages))
        throw UsageError(fmt::format("--mimages {}: a bricked run writes M-images brick by brick to .vti, .pvti or "
                                     ".hdf (the value and n1..n5 as point data)",
                                     o.mimages));
    const std::unique_ptr<Engine> engine = o.engine->tuned(o.engine_settings);
    const EngineCapabilities can = engine->capabilities();
    if (!can.exact || can.float32 || can.sign_only)
        throw UsageError(fmt::format(
            "a bricked run computes the float64 values of the exact engines ({}); --engine {} is not one of them{}",
            engine_names(", ", " and ", [](const EngineCapabilities& c) { return c.exact; }), engine->description(),
            // The fv engine (palette: M-images at every operation) cannot be cut into bricks at all.
            can.palette ? ": its value at a node is composed from the M-images of every operation, so it depends on "
                          "neighbours through the whole model and no overlap of bricks can make it exact"
                        : ""));
    const Grid grid = bricked_grid(model, o);
    check_outputs(o, grid);
    const BrickLayout layout = brick_layout(lead_output(o), grid, o.brick);
    // A .pvti: one piece per rank, or per layer of bricks on one process.
    const bool pvti = extension(o.output) == ".pvti" || extension(o.mimages) == ".pvti";
    const int pieces = pvti ? std::min(world.distributed() ? world.size() : layout.counts[2], layout.counts[2]) : 1;
    if (pvti && world.distributed() && pieces < world.size() && world.rank() == 0)
        std::cerr << fmt::format("fortu: note: {} pieces for {} ranks (the grid has {} layers of bricks along Z)\n",
                                 pieces, world.size(), layout.counts[2]);

    // Memory: the bricks in flight (values, with M-images the overlap and the components, a
    // .vdb's records) and each evaluator's scratch.
    const bool sparse = extension(o.output) == ".vdb";
    const bool mimages = !o.mimages.empty();
    const std::size_t brick_points = layout.brick_points();
    const std::size_t per_worker = brick_fields_bytes(layout, mimages) + (sparse ? 16 * brick_points : 0) +
                                   brick_evaluator_bytes(model.graph, model.root);
    const std::size_t base = peak_rss_bytes();
    const std::size_t bound = o.memory ? o.memory : available_memory();
    int threads = resolve_threads(o.threads);
    if (bound) {
        if (base + per_worker > bound)
            throw UsageError(fmt::format(
                "--memory {}: one brick of {}³ nodes{} needs about {} beside the {} this process holds; give a smaller "
                "--brick or more --memory",
                format_bytes(bound), o.brick,
                mimages ? fmt::format(" (with its overlap and the M-images' {} components)", fv_component_count(grid))
                        : "",
                format_bytes(per_worker), format_bytes(base)));
        const int fit = int(std::min<std::size_t>((bound - base) / per_worker, 1024));
        if (fit < threads) {
            if (world.rank() == 0)
                std::cerr << fmt::format("fortu: note: {} thread{} within --memory {} (a brick in flight each)\n", fit,
                                         fit == 1 ? "" : "s", format_bytes(bound));
            threads = fit;
        }
    }

    // The done map (named after the lead output) and the partial outputs, -o's and the
    // M-images': rank 0 starts (or resumes) them, the others join; a collective file is
    // opened by every rank at once (parallel HDF5).
    const std::string key = run_key(model, layout, pieces, o, *engine);
    std::vector<BrickOutputSpec> specs;
    for (const std::string* path : {&o.output, &o.mimages}) {
        if (path->empty()) continue;
        const bool collective = brick_output_collective(*path);
        specs.push_back({*path, layout, o.vdb_band, world.rank(), true, pieces, collective && world.distributed(),
                         &world.mpi_mutex(), path == &o.mimages});
    }
    const std::string& lead = lead_output(o);
    const bool resumable = std::filesystem::exists(done_map_path(lead)) &&
                           std::all_of(specs.begin(), specs.end(), [](const auto& s) { return brick_partials_exist(s); });
    if (o.resume && !resumable && world.rank() == 0)
        std::cerr << fmt::format("fortu: note: no unfinished run of '{}' to resume; starting afresh\n", lead);
    const bool resume = o.resume && resumable;
    std::vector<std::unique_ptr<BrickOutput>> outputs(specs.size());
    std::unique_ptr<DoneMap> done;
    auto open_outputs = [&](bool collective, bool create) {
        for (std::size_t i = 0; i < specs.size(); ++i) {
            if (brick_output_collective(specs[i].path) != collective) continue;
            BrickOutputSpec mine = specs[i];
            mine.create = create;
            outputs[i] = open_brick_output(mine);
        }
    };
    auto open = [&](bool first) {
        open_outputs(false, first && !resume);
        done = std::make_unique<DoneMap>(lead, key, first ? (resume ? DoneMap::Mode::Resume : DoneMap::Mode::Fresh)
                                                          : DoneMap::Mode::Join);
    };
    try {
        if (world.rank() == 0) open(true);
        world.barrier();
        if (world.rank() != 0) open(false);
        open_outputs(true, !resume);
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        if (world.distributed()) world.abort(1);
        return 1;
    }
    std::vector<std::size_t> todo;
    for (std::size_t b = 0; b < layout.size(); ++b)
        if (!done->done().count(b)) todo.push_back(b);

    // --brick-times: appended line by line, by every rank.
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> times_file(nullptr, std::fclose);
    if (!o.brick_times.empty() && !(times_file.reset(std::fopen(o.brick_times.c_str(), "a")), times_file))
        throw UsageError(fmt::format("--brick-times: cannot open '{}'", o.brick_times));
    std::FILE* times = times_file.get();
    std::mutex times_mutex;

    Stopwatch clock;
    const double cpu_start = cpu_seconds();
    std::vector<WorkerStats> stats(threads);
    std::exception_ptr failure;
    std::mutex failure_mutex;
    std::atomic<bool> stop{false};
    {
        World::Counter counter(world);
        DoneRecorder recorder(*done, [&] {
            for (const auto& output : outputs) output->sync();
        });
        // A sparse -o alone may skip what lies beyond its band; components need every value.
        const std::optional<double> skip_beyond = mimages ? std::nullopt : outputs.front()->skip_beyond();
        auto work = [&](int worker) {
            try {
                BrickFieldEvaluator evaluator(model.graph, model.root, grid, mimages);
                BrickFields fields;
                WorkerStats& st = stats[worker];
                while (!stop) {
                    const std::uint64_t n = counter.next();
                    if (n >= todo.size()) break;
                    const BrickBox box = layout.box(todo[n]);
                    Stopwatch brick_clock;
                    const BrickStats b = evaluator.evaluate(box, fields, skip_beyond);
                    for (std::size_t i = 0; i < outputs.size(); ++i)
                        outputs[i]->write(todo[n], box, fields.values,
                                          specs[i].mimages ? std::span<const double>(fields.components)
                                                           : std::span<const double>());
                    recorder.finished(todo[n]);
                    const double seconds = brick_clock.seconds();
                    ++st.bricks;
                    st.brick_seconds += seconds;
                    st.max_brick_seconds = std::max(st.max_brick_seconds, seconds);
                    st.evaluated += b.evaluated_points;
                    st.skipped += b.skipped_points;
                    if (times) {
                        std::lock_guard lock(times_mutex);
                        std::fprintf(times, "%zu,%d,%.6f,%zu,%zu\n", todo[n], world.rank(), seconds,
                                     b.evaluated_points, b.skipped_points);
                        std::fflush(times);
                    }
                }
            } catch (...) {
                std::lock_guard lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                stop = true;
            }
        };
        std::vector<std::jthread> pool;
        for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
        work(0);
        pool.clear();
        if (!failure) {
            try {
                recorder.flush();   // this rank's bricks are on disk and in the map
            } catch (...) {
                failure = std::current_exception();
            }
        }
        if (failure) {
            try {
                std::rethrow_exception(failure);
            } catch (const std::exception& e) {
                std::cerr << fmt::format("fortu: error: {}\n", e.what());
            }
            if (world.distributed()) world.abort(1);
            return 1;
        }
    }
    times_file.reset();
    try {
        for (const auto& output : outputs) output->close();
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        if (world.distributed()) world.abort(1);
        return 1;
    }
    const double evaluate_seconds = clock.seconds();
    const double cpu = cpu_seconds() - cpu_start;
    world.barrier();

    Stopwatch assemble_clock;
    if (world.rank() == 0) {
        try {
            for (const auto& output : outputs) output->finish(bound > base ? bound - base : 0);
            done->remove();
        } catch (const OutputError& e) {
            std::cerr << fmt::format("fortu: error: {}\n", e.what());
            if (world.distributed()) world.abort(1);
            return 1;
        }
    }
    const double assemble_seconds = assemble_clock.seconds();

    WorkerStats mine;
    for (const WorkerStats& s : stats) {
        mine.bricks += s.bricks;
        mine.brick_seconds += s.brick_seconds;
        mine.max_brick_seconds = std::max(mine.max_brick_seconds, s.max_brick_seconds);
        mine.evaluated += s.evaluated;
        mine.skipped += s.skipped;
    }
    const std::vector<double> all = world.gather({double(mine.bricks), mine.brick_seconds, mine.max_brick_seconds, cpu,
                                                  double(mine.evaluated), double(mine.skipped), double(peak_rss_bytes())});
    if (o.stats && world.rank() == 0) {
        constexpr int kFields = 7;
        double evaluated = 0, skipped = 0, cpu_sum = 0, busy_max = 0, busy_sum = 0;
        std::string ranks;
        for (int r = 0; r < world.size(); ++r) {
            const double* f = all.data() + kFields * r;
            evaluated += f[4];
            skipped += f[5];
            cpu_sum += f[3];
            busy_max = std::max(busy_max, f[1]);
            busy_sum += f[1];
            ranks += fmt::format("rank {}: {} bricks, brick time {:.3f} s (longest {:.3f} s), cpu {:.3f} s, peak memory {}\n",
                                 r, f[0], f[1], f[2], f[3], format_bytes(std::size_t(f[6])));
        }
        const double mean = busy_sum / world.size();
        std::cout << fmt::format(
            "model: {}\ngrid: {} = {} points, {} bricks of {}x{}x{} nodes ({} from the done map, {} computed)\n"
            "engine: {} (bricks: interval-pruned tapes, exact values), ranks: {}, threads per rank: {}\n"
            "points: {} evaluated, {} decided by intervals (outside the .vdb band)\n"
            "time: compile {:.3f} s, bricks {:.3f} s, assemble {:.3f} s; cpu (all ranks) {:.3f} s\n"
            "{}load balance: max/mean brick time per rank {:.3f}\n",
            o.positional[0], grid_text(grid), format_count(grid.points()), layout.size(),
            std::min(layout.shape[0], grid.cols()), std::min(layout.shape[1], grid.rows()),
            std::min(layout.shape[2], grid.slices()),
            layout.size() - todo.size(), todo.size(), engine->description(), world.size(), threads,
            format_count(std::uint64_t(evaluated)), format_count(std::uint64_t(skipped)), compile_seconds,
            evaluate_seconds, assemble_seconds, cpu_sum, ranks, mean > 0 ? busy_max / mean : 1.0);
    }
    return 0;
}

}  // namespace fortu
