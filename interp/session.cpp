// interp/session.cpp — the REPL's accumulated script: statements kept as slices of what was
// typed, re-assembled and compiled after each change, diagnostics mapped back to the input.
#include "interp/session.hpp"

#include "grammar/ast.hpp"
#include "grammar/parse.hpp"
#include "interp/grid_size.hpp"
#include "interp/lower.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <set>
#include <span>
#include <fmt/format.h>

namespace fortu {
namespace {

using Kind = SubmitResult::Kind;

/// The byte offset of a position in its file.
std::size_t offset_of(const SourceFile& file, SourcePos pos) {
    if (pos.line > file.line_count()) return file.text().size();
    const std::string_view line = file.line(pos.line);
    const std::size_t start = static_cast<std::size_t>(line.data() - file.text().data());
    return std::min(file.text().size(), start + static_cast<std::size_t>(std::max(pos.column, 1) - 1));
}

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

/// True if `expr` uses `name` (a reference or a call): such a definition refines the earlier
/// one (`D = D & C`) rather than replacing it.
bool mentions(const ast::Expr& expr, const std::string& name) {
    if ((expr.kind == ast::Expr::Kind::Name || expr.kind == ast::Expr::Kind::Call) && expr.name == name)
        return true;
    for (const ast::ExprPtr& operand : expr.operands)
        if (operand && mentions(*operand, name)) return true;
    return false;
}

uint64_t mix(uint64_t h, uint64_t v) {
    // splitmix64's finaliser over an FNV-style chain: cheap, and well spread for map keys.
    h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h ^= h >> 30;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 27;
    h *= 0x94d049bb133111ebULL;
    return h ^ (h >> 31);
}

uint64_t bits_of(double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

uint64_t grid_key(const Grid& g) {
    uint64_t h = mix(0, static_cast<uint64_t>(g.dims));
    for (const Axis* a : {&g.x, &g.y, &g.z})
        h = mix(mix(mix(h, bits_of(a->min)), bits_of(a->max)), static_cast<uint64_t>(a->nodes));
    return h;
}

std::string number(double v) { return fmt::format("{}", v); }

/// Memory for kept values: 256 MiB is 512 definitions on the default 256² grid.
constexpr std::size_t kKeptBytes = std::size_t{256} << 20;
/// Each kept definition is one more tape output, live to the end of every tile.
constexpr std::size_t kMaxKeptPerEvaluation = 64;

}  // namespace

std::vector<uint64_t> structural_hashes(const ir::Graph& graph, ir::NodeId root) {
    std::vector<uint64_t> hashes(graph.size(), 0);
    if (root == ir::kNoNode) return hashes;
    for (ir::NodeId id : graph.reachable(root)) {
        const ir::Node& n = graph.node(id);
        std::array<uint64_t, ir::kMaxArity> operands{};
        const int arity = ir::op_arity(n.op);
        for (int k = 0; k < arity; ++k) operands[k] = hashes[n.args[k]];
        // Graph::make orders commutative operands by id, which depends on the graph; order
        // them by hash instead, so a + b and b + a hash alike in any graph.
        if ((ir::op_flags(n.op) & ir::kCommutative) && arity == 2 && operands[1] < operands[0])
            std::swap(operands[0], operands[1]);
        uint64_t h = mix(static_cast<uint64_t>(n.op) + 1, bits_of(n.imm));
        for (int k = 0; k < arity; ++k) h = mix(h, operands[k]);
        hashes[id] = h;
    }
    return hashes;
}

/// The session as one script, and which of its lines came from which entry.
struct Session::Assembled {
    std::string text;
    struct Span {
        int first_line = 0;     ///< the entry's first slice line in `text`
        int last_line = 0;
        const Entry* entry = nullptr;
    };
    std::vector<Span> spans;
};

Session::Session(std::vector<std::string> include_dirs) : include_dirs_(std::move(include_dirs)) {}

void Session::reset() {
    entries_.clear();
    model_.reset();
    rsystem_.reset();
    domain_ = {};
    size_.clear();
    section_ = "VARIABLE";
    kept_.clear();
}

Session::Assembled Session::assemble(const std::vector<Entry>& entries, const Entry* probe) const {
    Assembled out;
    int line = 1;
    auto add = [&](const Entry& e) {
        if (!e.keyword.empty()) {
            // The keyword on a line of its own: a line ending in a keyword continues the
            // statement (spec §1), and the slice keeps its own line and column numbers.
            out.text += e.keyword + "\n";
            ++line;
        }
        const std::size_t from = offset_of(*e.file, e.begin), to = offset_of(*e.file, e.end);
        out.text += std::string(static_cast<std::size_t>(std::max(e.begin.column, 1) - 1), ' ');
        out.text += e.file->text().substr(from, to - from);
        out.text += "\n";
        const int lines = e.end.line - e.begin.line + 1;
        out.spans.push_back({line, line + lines - 1, &e});
        line += lines;
    };
    using K = Entry::Kind;
    for (K header : {K::RSystem, K::Rectangle, K::RectBmp, K::Argument}) {
        bool found = false;
        for (const Entry& e : entries)
            if (e.kind == header) { add(e); found = true; }
        if (header == K::Argument && !found) { out.text += "ARGUMENT X, Y\n"; ++line; }
    }
    const Entry* ret = probe;
    for (const Entry& e : entries) {
        if (e.kind == K::Return) { if (!ret) ret = &e; continue; }
        if (e.kind == K::RSystem || e.kind == K::Rectangle || e.kind == K::RectBmp || e.kind == K::Argument)
            continue;
        add(e);
    }
    // Until a RETURN is typed the definitions are still checked, against a constant model.
    if (ret) add(*ret);
    else out.text += "RETURN 0\n";
    return out;
}

std::optional<SubmitResult> Session::try_compile(const std::vector<Entry>& entries, const Entry* probe,
                                                 const SourceFile* typed, std::optional<Model>& out) const {
    const Assembled assembled = assemble(entries, probe);
    auto file = std::make_shared<SourceFile>("<session>", assembled.text);
    CompileOptions options;
    options.rsystem = rsystem_;
    options.include_dirs = include_dirs_;
    DiagnosticSink sink;
    out = compile(file, options, sink);

    // Diagnostics in the assembled text go back to the line as typed (or loaded).
    std::string errors, warnings;
    for (Diagnostic d : sink.diagnostics()) {
        const SourceFile* shown = d.range.file;
        if (d.range.file == file.get()) {
            for (const Assembled::Span& s : assembled.spans) {
                if (d.range.begin.line > s.last_line) continue;
                const int shift = s.entry->begin.line - s.first_line;
                d.range.file = s.entry->file.get();
                d.range.begin.line = std::max(d.range.begin.line, s.first_line) + shift;
                d.range.end.line = std::clamp(d.range.end.line, s.first_line, s.last_line) + shift;
                if (d.range.end.line == d.range.begin.line && d.range.end.column < d.range.begin.column)
                    d.range.end = d.range.begin;
                shown = d.range.file;
                break;
            }
        }
        if (d.severity == Severity::Error) errors += render(d);
        else if (d.severity == Severity::Warning && typed && shown == typed) warnings += render(d);
    }
    if (!out) {
        SubmitResult r;
        r.kind = Kind::Error;
        r.diagnostics = errors.empty() ? "fortu: error: the session does not compile\n" : errors;
        return r;
    }
    SubmitResult r;
    r.diagnostics = warnings;
    return r;
}

SubmitResult Session::submit(const std::string& text, const std::string& origin) {
    auto file = std::make_shared<SourceFile>(origin, text);
    DiagnosticSink sink;
    ast::Script script = parse_script(*file, sink);
    using K = Entry::Kind;

    if (sink.has_errors()) {
        // Not statements: perhaps one expression, to evaluate at the probe point.
        SourceFile as_return("<expression>", "RETURN\n" + text);
        DiagnosticSink ignored;
        ast::Script probe_script = parse_script(as_return, ignored);
        if (!ignored.has_errors() && probe_script.statements.size() == 1 &&
            std::holds_alternative<ast::ReturnStmt>(probe_script.statements[0].node)) {
            const ast::Expr& value = *std::get<ast::ReturnStmt>(probe_script.statements[0].node).value;
            // The whole input, minus the RETURN line that was added in front of it.
            Entry probe{K::Return, "", "RETURN", file, {1, 1}, {value.range.end.line - 1, value.range.end.column}};
            std::optional<Model> model;
            SubmitResult r = *try_compile(entries_, &probe, file.get(), model);
            if (r.kind == Kind::Error) return r;
            r.kind = Kind::Expression;
            r.model = std::move(model);
            return r;
        }
        SubmitResult r;
        r.kind = Kind::Error;
        r.diagnostics = sink.render_all();
        return r;
    }
    if (script.statements.empty()) return {};

    std::vector<Entry> entries = entries_;
    std::vector<std::string> changes;
    std::vector<std::string> replaced_functions;
    std::string section = section_;
    auto replace_or_append = [&](Entry e, bool replace) {
        for (Entry& old : entries) {
            if (!replace || old.kind != e.kind || old.name != e.name) continue;
            old = std::move(e);
            return true;
        }
        entries.push_back(std::move(e));
        return false;
    };
    for (const ast::Statement& st : script.statements) {
        const std::string_view lead = std::string_view(text).substr(offset_of(*file, st.range.begin));
        Entry e{K::For, "", "", file, st.range.begin, st.range.end};
        std::visit(
            [&](const auto& node) {
                using T = std::decay_t<decltype(node)>;
                if constexpr (std::is_same_v<T, ast::Definition>) {
                    // A keyword of its own (CONSTANT R = ...) sets the section in force; a
                    // bare `R = ...` re-defining R keeps R's section, else takes the one in force.
                    const bool has_keyword = st.range.begin.line != node.name_range.begin.line ||
                                             st.range.begin.column != node.name_range.begin.column;
                    const std::string parsed = node.section == ast::Section::Constant ? "CONSTANT" : "VARIABLE";
                    if (has_keyword) section = parsed;
                    e.kind = K::Definition;
                    e.name = node.name;
                    e.begin = node.name_range.begin;
                    e.end = node.value->range.end;
                    e.keyword = has_keyword ? parsed : section;
                    e.inferred = !has_keyword;
                    const bool refines = mentions(*node.value, node.name);
                    if (!has_keyword && !refines)
                        for (const Entry& old : entries)
                            if (old.kind == K::Definition && old.name == node.name) { e.keyword = old.keyword; break; }
                    const bool replaced = replace_or_append(std::move(e), !refines);
                    changes.push_back(fmt::format("{} {}", replaced ? "replaced" : refines ? "refined" : "defined", node.name));
                } else if constexpr (std::is_same_v<T, ast::ReturnStmt>) {
                    e.kind = K::Return;
                    e.keyword = "RETURN";
                    e.begin = node.value->range.begin;
                    e.end = node.value->range.end;
                    replace_or_append(std::move(e), true);
                    changes.push_back("model set");
                } else if constexpr (std::is_same_v<T, ast::FunctionDef>) {
                    e.kind = K::Function;
                    e.name = node.name;
                    const bool replaced = replace_or_append(std::move(e), true);
                    if (replaced) replaced_functions.push_back(node.name);
                    changes.push_back(fmt::format("{} {}", replaced ? "replaced" : "defined", node.name));
                } else if constexpr (std::is_same_v<T, ast::IncludeStmt>) {
                    e.kind = K::Include;
                    e.name = node.path;
                    replace_or_append(std::move(e), true);
                    changes.push_back(fmt::format("included {}", node.path));
                } else if constexpr (std::is_same_v<T, ast::ForStmt>) {
                    entries.push_back(std::move(e));
                    changes.push_back("loop");
                } else {
                    if constexpr (std::is_same_v<T, ast::ArgumentStmt>) e.kind = K::Argument;
                    if constexpr (std::is_same_v<T, ast::RectangleStmt>) e.kind = K::Rectangle;
                    if constexpr (std::is_same_v<T, ast::RectBmpStmt>) e.kind = K::RectBmp;
                    if constexpr (std::is_same_v<T, ast::RSystemStmt>) e.kind = K::RSystem;
                    replace_or_append(std::move(e), true);
                    changes.push_back(upper(lead.substr(0, lead.find_first_of(" \t(\r\n"))));
                }
            },
            st.node);
    }

    // INCLUDE in a loaded file is relative to that file.
    const std::filesystem::path folder = std::filesystem::path(origin).parent_path();
    if (!origin.empty() && origin.front() != '<' && !folder.empty() &&
        std::find(include_dirs_.begin(), include_dirs_.end(), folder.string()) == include_dirs_.end())
        include_dirs_.insert(include_dirs_.begin(), folder.string());

    std::optional<Model> model;
    SubmitResult r = *try_compile(entries, nullptr, file.get(), model);
    if (r.kind == Kind::Error) {
        // A bare `D = R - SQRT(X^2 + Y^2)` typed while CONSTANT is in force means a
        // VARIABLE: in a file it would be an error, at a prompt it is what was meant.
        bool retry = false;
        for (Entry& e : entries)
            if (e.inferred && e.keyword == "CONSTANT") { e.keyword = "VARIABLE"; retry = true; }
        if (retry) r = *try_compile(entries, nullptr, file.get(), model);
    }
    if (r.kind == Kind::Error && !replaced_functions.empty()) {
        // A function body sees only what is written before it (lexical binding), so a new
        // body using names defined after the old one's place cannot stay there: it moves to
        // the end, where it sees every definition (what used the old one after its place
        // then reports it unknown, as a file written in that order would).
        std::vector<Entry> moved = entries;
        for (const std::string& name : replaced_functions) {
            const auto it = std::find_if(moved.begin(), moved.end(),
                                         [&](const Entry& e) { return e.kind == K::Function && e.name == name; });
            if (it == moved.end()) continue;
            Entry function = std::move(*it);
            moved.erase(it);
            moved.push_back(std::move(function));
        }
        std::optional<Model> moved_model;
        SubmitResult moved_result = *try_compile(moved, nullptr, file.get(), moved_model);
        if (moved_result.kind != Kind::Error) {
            entries = std::move(moved);
            model = std::move(moved_model);
            r = std::move(moved_result);
        }
    }
    if (r.kind == Kind::Error) return r;
    for (Entry& e : entries) e.inferred = false;
    entries_ = std::move(entries);
    section_ = section;
    const bool has_return = std::any_of(entries_.begin(), entries_.end(), [](const Entry& e) { return e.kind == K::Return; });
    if (has_return) model_ = std::move(model);
    else model_.reset();
    r.kind = Kind::Statements;
    r.changes = std::move(changes);
    return r;
}

void Session::set_rsystem(std::optional<RSystem> rsystem) {
    rsystem_ = rsystem;
    std::optional<Model> model;
    if (try_compile(entries_, nullptr, nullptr, model)->kind != Kind::Error && model_) model_ = std::move(model);
}

Grid Session::grid() const {
    if (model_) return sized_grid(*model_, size_, domain_);
    // No model yet: the 2D grid a two-argument model would get.
    Grid grid;
    Axis* axes[2] = {&grid.x, &grid.y};
    for (int a = 0; a < 2; ++a) {
        const AxisRange r = domain_[a].value_or(AxisRange{});
        axes[a]->min = r.min;
        axes[a]->max = r.max;
        axes[a]->nodes = size_.empty() ? 256 : size_[std::min<std::size_t>(a, size_.size() - 1)];
    }
    return grid;
}

std::vector<std::string> Session::names() const {
    std::vector<std::string> out;
    auto add = [&out](const std::string& name) {
        if (!name.empty() && std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    };
    if (model_)
        for (const std::string& a : model_->arguments) add(a);
    for (const Entry& e : entries_)
        if (e.kind == Entry::Kind::Definition || e.kind == Entry::Kind::Function) add(e.name);
    return out;
}

Grid Session::grid_with_nodes(int cols, int rows) const {
    Grid grid = this->grid();
    grid.x.nodes = std::max(cols, 1);
    grid.y.nodes = grid.y.nodes == 1 && model_ && model_->arguments.size() == 1 ? 1 : std::max(rows, 1);
    if (grid.dims == 3) {
        grid.z.min = grid.z.max = (grid.z.min + grid.z.max) / 2;
        grid.z.nodes = 1;
    }
    return grid;
}

const std::vector<double>* Session::find_kept(uint64_t key) {
    for (auto it = kept_.begin(); it != kept_.end(); ++it) {
        if (it->key != key) continue;
        kept_.splice(kept_.begin(), kept_, it);   // moves no values: pointers stay valid
        return &kept_.front().values;
    }
    return nullptr;
}

void Session::keep(uint64_t key, std::vector<double> values) {
    kept_.push_front({key, std::move(values)});
    std::size_t bytes = 0;
    for (auto it = kept_.begin(); it != kept_.end(); ++it) {
        bytes += it->values.size() * sizeof(double);
        if (bytes > kKeptBytes && it != kept_.begin()) {
            kept_.erase(it, kept_.end());
            break;
        }
    }
}

Field Session::evaluate(const Grid& grid, const Engine& engine, const EvalOptions& options, EvalReport& report) {
    report = EvalReport{};
    report.engine = std::string(engine.name());
    report.grid = grid;
    const Model& m = *model_;
    const ir::Graph& graph = m.graph;
    const std::vector<uint64_t> hashes = structural_hashes(graph, m.root);
    const uint64_t grid_and_precision = mix(grid_key(grid), engine.capabilities().float32 ? 1 : 0);
    auto key_of = [&](ir::NodeId id) { return mix(hashes[id], grid_and_precision); };
    auto count_operations = [&](const std::vector<ir::NodeId>& nodes, const std::vector<char>* stop) {
        std::size_t n = 0;
        for (ir::NodeId id : nodes) n += !(stop && (*stop)[id]) && !(ir::op_flags(graph.node(id).op) & ir::kLeaf);
        return n;
    };
    const std::vector<ir::NodeId> all = graph.reachable(m.root);
    report.operations = count_operations(all, nullptr);

    Field field;
    field.grid = grid;
    if (const std::vector<double>* values = find_kept(key_of(m.root))) {
        field.values = *values;
        report.reused = true;
        return field;
    }

    // An engine with known_and_kept reads the definitions whose values are kept instead of
    // computing them (the classic engine, by definition, saves nothing); those still
    // computed are kept.
    NodeValues run;
    std::vector<char> known(graph.size(), 0);
    std::vector<std::pair<ir::NodeId, std::vector<double>>> fresh;
    std::vector<ir::NodeId> computed = all;
    if (engine.capabilities().known_and_kept) {
        std::vector<char> reachable(graph.size(), 0), listed(graph.size(), 0);
        for (ir::NodeId id : all) reachable[id] = 1;
        for (const auto& [name, node] : m.definitions) {
            if (!reachable[node] || node == m.root || listed[node]) continue;
            listed[node] = 1;
            if (const std::vector<double>* values = find_kept(key_of(node))) {
                run.known.emplace_back(node, values->data());
                known[node] = 1;
            }
        }
        computed = graph.reachable(std::span(&m.root, 1), &known);
        std::vector<char> to_compute(graph.size(), 0), read(graph.size(), 0);
        for (ir::NodeId id : computed) (known[id] ? read[id] : to_compute[id]) = 1;
        // Reported: the kept values actually read, not those under another read definition.
        for (const auto& [name, node] : m.definitions)
            if (read[node]) {
                report.reused_definitions.push_back(name);
                read[node] = 0;
            }
        // Kept: the last definition of each name (a FOR loop's redefinitions are one
        // cell), latest first (they build on earlier ones), within a count and memory cap.
        std::set<std::string> named;
        std::size_t bytes = 0;
        for (auto it = m.definitions.rbegin(); it != m.definitions.rend(); ++it) {
            const auto& [name, node] = *it;
            if (!named.insert(name).second || !to_compute[node] || node == m.root) continue;
            to_compute[node] = 0;   // once, if two names define the same node
            bytes += grid.points() * sizeof(double);
            if (fresh.size() == kMaxKeptPerEvaluation || bytes > kKeptBytes / 2) break;
            fresh.emplace_back(node, std::vector<double>(grid.points()));
        }
        for (auto& [node, values] : fresh) run.keep.emplace_back(node, values.data());
    }
    report.computed_operations = count_operations(computed, &known);

    const auto start = std::chrono::steady_clock::now();
    field = engine.evaluate_grid(graph, m.root, grid, options, run);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.cancel && options.cancel->load()) {
        report.cancelled = true;
        return field;
    }
    for (auto& [node, values] : fresh) keep(key_of(node), std::move(values));
    report.kept_definitions = fresh.size();
    keep(key_of(m.root), field.values);
    return field;
}

std::string Session::script() const {
    using K = Entry::Kind;
    std::string out = "// A fortu repl session, saved with :save.\n";
    if (rsystem_) {
        if (rsystem_->alpha == 0.0) out += "RSYSTEM R0\n";
        else if (rsystem_->alpha == 1.0) out += "RSYSTEM MINMAX\n";
        else out += fmt::format("RSYSTEM ALPHA = {}\n", number(rsystem_->alpha));
    } else {
        for (const Entry& e : entries_)
            if (e.kind == K::RSystem) out += std::string(e.file->text().substr(offset_of(*e.file, e.begin), offset_of(*e.file, e.end) - offset_of(*e.file, e.begin))) + "\n";
    }
    // The grid as the script's own: RECTBMP (2D) and a range on every argument.
    const Grid g = grid();
    const std::vector<std::string> names = model_ ? model_->arguments : std::vector<std::string>{};
    bool wrote_arguments = false;
    if (!names.empty()) {
        if (g.dims == 2) out += fmt::format("RECTBMP({}, {})\n", g.cols(), g.rows());
        else out += fmt::format("// sampled on {}x{}x{} nodes: fortu run --size {}x{}x{}\n", g.cols(), g.rows(),
                                g.slices(), g.cols(), g.rows(), g.slices());
        const Axis* axes[3] = {&g.x, &g.y, &g.z};
        std::string list;
        for (std::size_t a = 0; a < names.size(); ++a)
            list += fmt::format("{}{}({}, {})", a ? ", " : "", names[a], number(axes[a]->min), number(axes[a]->max));
        out += "ARGUMENT " + list + "\n";
        wrote_arguments = true;
    }
    auto slice = [](const Entry& e) {
        const std::size_t from = offset_of(*e.file, e.begin), to = offset_of(*e.file, e.end);
        return e.file->text().substr(from, to - from);
    };
    for (const Entry& e : entries_) {
        const bool header = e.kind == K::Rectangle || e.kind == K::RectBmp || e.kind == K::Argument;
        if (header && !wrote_arguments) out += std::string(slice(e)) + "\n";   // no model yet: as typed
        if (e.kind == K::RSystem || e.kind == K::Rectangle || e.kind == K::RectBmp || e.kind == K::Argument ||
            e.kind == K::Return)
            continue;
        out += (e.keyword.empty() ? "" : e.keyword + " ") + std::string(slice(e)) + "\n";
    }
    for (const Entry& e : entries_)
        if (e.kind == K::Return) out += "RETURN " + std::string(slice(e)) + "\n";
    return out;
}

}  // namespace fortu
