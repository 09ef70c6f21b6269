// interp/lower.cpp — semantic checks and lowering of a FORTU script to the IR.
#include "interp/lower.hpp"

#include "grammar/ast.hpp"
#include "grammar/parse.hpp"
#include "interp/header_domain.hpp"
#include "interp/large_stack.hpp"
#include "interp/source_loader.hpp"
#include "runtime/image_table.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdint>
#include <deque>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <set>
#include <unordered_map>

namespace fortu {
namespace {

using ir::NodeId;
using ir::Op;

std::string lower_case(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string format_number(double v) { return fmt::format("{}", v); }

// ---- built-ins ----------------------------------------------------------------------

struct Builtin {
    std::string_view name;
    Op op;
    int min_args;
    int max_args;   ///< -1: any number >= min_args (MIN, MAX fold left)

    bool takes(int argc) const { return argc >= min_args && (max_args < 0 || argc <= max_args); }
};

// ops.def's FORTU_BUILTIN lines. SIZE (op Const) is the special form handled in lower_call.
constexpr Builtin kBuiltins[] = {
#define FORTU_BUILTIN(spelling, name, min_args, max_args) {spelling, Op::name, min_args, max_args},
#include "interp/ir/ops.def"
};

bool same_name(std::string_view builtin, std::string_view name) {
    return builtin.size() == name.size() &&
           std::equal(name.begin(), name.end(), builtin.begin(), [](char a, char b) {
               return std::toupper(static_cast<unsigned char>(a)) == b;
           });
}

/// The built-in spelled `name` (any case) that takes `argc` arguments, or, when none
/// does, the first one spelled so; nullptr when there is none.
const Builtin* find_builtin(std::string_view name, int argc = -1) {
    const Builtin* first = nullptr;
    for (const Builtin& b : kBuiltins) {
        if (!same_name(b.name, name)) continue;
        if (b.takes(argc)) return &b;
        if (!first) first = &b;
    }
    return first;
}

/// The argument counts a spelling takes over all its lines (ATAN: 1 or 2); max -1: no limit.
std::pair<int, int> argument_counts(std::string_view name) {
    int low = INT_MAX, high = 0;
    for (const Builtin& b : kBuiltins) {
        if (b.name != name) continue;
        low = std::min(low, b.min_args);
        high = (high < 0 || b.max_args < 0) ? -1 : std::max(high, b.max_args);
    }
    return {low, high};
}

std::string plural(int n, const char* word) {
    return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

// ---- scope --------------------------------------------------------------------------

class Scope;

/// A point in one scope's history: the names defined there up to it.
struct ScopeMark {
    const Scope* scope = nullptr;
    std::uint64_t version = UINT64_MAX;   ///< UINT64_MAX: everything defined so far
};

struct Binding {
    enum class Kind { Argument, Constant, Variable, Array, Function };
    Kind kind = Kind::Variable;
    std::string name;
    SourceRange where;
    NodeId node = ir::kNoNode;
    std::vector<double> array;
    const ast::FunctionDef* function = nullptr;
    ScopeMark written_at;   ///< Function: where it is written, the names its body sees
};

const char* kind_word(Binding::Kind kind) {
    switch (kind) {
        case Binding::Kind::Argument: return "argument";
        case Binding::Kind::Constant: return "constant";
        case Binding::Kind::Variable: return "variable";
        case Binding::Kind::Array: return "array";
        case Binding::Kind::Function: return "function";
    }
    return "name";
}

/// Names in force at one point of the script. Re-definition shadows a binding (SSA
/// renaming: each use sees the latest definition before it). A function body is a use at
/// its own place in the text (lexical binding, spec §2): a FUNCTION records that place (a
/// ScopeMark) and its calls see the names in force there, not at the call; so a binding a
/// function written since may still see is kept when its name is re-defined, and only then.
/// Function calls push a child scope for parameters and local definitions, whose parent is
/// the function's mark.
class Scope {
public:
    explicit Scope(ScopeMark parent = {}) : parent_(parent) {}

    void define(Binding binding) {
        const std::string key = binding.name;
        ++version_;
        folded_[lower_case(key)].emplace(key, version_);   // keeps the first version of a spelling
        if (binding.kind == Binding::Kind::Function) {
            binding.written_at = ScopeMark{this, version_};   // sees itself: recursion is reported as such
            marked_ = version_;
        }
        std::deque<Versioned>& history = bindings_[key];   // a deque: bindings never move
        if (!history.empty() && history.back().version > marked_) history.pop_back();   // no function saw it
        history.push_back(Versioned{version_, std::move(binding)});
    }
    bool top_level() const { return parent_.scope == nullptr; }
    const Binding* exact(const std::string& name, std::uint64_t up_to = UINT64_MAX) const {
        if (auto it = bindings_.find(name); it != bindings_.end())
            for (auto v = it->second.rbegin(); v != it->second.rend(); ++v)
                if (v->version <= up_to) return &v->binding;
        return parent_.scope ? parent_.scope->exact(name, parent_.version) : nullptr;
    }
    /// Distinct spellings, in this scope and its parents, equal to `name` ignoring case.
    void case_matches(const std::string& name, std::set<std::string>& out, std::uint64_t up_to = UINT64_MAX) const {
        if (auto it = folded_.find(lower_case(name)); it != folded_.end())
            for (const auto& [spelling, first] : it->second)
                if (first <= up_to) out.insert(spelling);
        if (parent_.scope) parent_.scope->case_matches(name, out, parent_.version);
    }

private:
    struct Versioned {
        std::uint64_t version;
        Binding binding;
    };
    ScopeMark parent_;
    std::uint64_t version_ = 0;   ///< of the latest definition
    std::uint64_t marked_ = 0;    ///< of the latest FUNCTION
    std::unordered_map<std::string, std::deque<Versioned>> bindings_;
    std::unordered_map<std::string, std::map<std::string, std::uint64_t>> folded_;
};

// ---- the lowering pass ----------------------------------------------------------------

enum class Context { Constant, Variable };

class Lowerer {
public:
    Lowerer(const CompileOptions& options, DiagnosticSink& sink, Model& model)
        : options_(options), loader_(options.loader ? *options.loader : disk_source_loader()), sink_(sink),
          model_(model), graph_(model.graph) {}

    void run(const std::shared_ptr<const SourceFile>& source) {
        included_.insert(loader_.identity(source->path()));
        including_.push_back({loader_.identity(source->path()), source->path()});
        const int errors_before = sink_.error_count();
        ast::Script script = parse_script(*source, sink_);
        // Syntax errors leave holes in the tree (a definition lost to recovery); checking
        // what remains would only report their echoes ("unknown name", "no RETURN").
        if (sink_.error_count() != errors_before) return;
        if (script.statements.empty()) {
            sink_.error(at_start(*source),
                        "empty script: expected ARGUMENT, definitions and RETURN");
            return;
        }
        lower_block(script.statements, global_);
        if (!syntax_errors_) finish(*source, script);
    }

private:
    // -- statements --

    void lower_block(const std::vector<ast::Statement>& statements, Scope& scope) {
        for (const ast::Statement& statement : statements) {
            if (too_many_errors() || !spend_work(statement.range)) return;
            if (return_seen_ && scope_depth_ == 0 && !warned_after_return_ &&
                !std::holds_alternative<ast::ReturnStmt>(statement.node)) {
                sink_.warning(statement.range, "statement after RETURN is ignored");
                warned_after_return_ = true;
            }
            if (return_seen_ && scope_depth_ == 0 &&
                !std::holds_alternative<ast::ReturnStmt>(statement.node))
                continue;
            std::visit([&](const auto& node) { lower_statement(statement, node, scope); },
                       statement.node);
        }
    }

    void lower_statement(const ast::Statement&, const ast::ArgumentStmt& stmt, Scope& scope) {
        for (const ast::ArgumentDecl& decl : stmt.arguments) {
            if (std::find(model_.arguments.begin(), model_.arguments.end(), decl.name) !=
                model_.arguments.end()) {
                sink_.error(decl.range, fmt::format("argument '{}' declared twice", decl.name));
                continue;
            }
            if (model_.arguments.size() == 3) {
                sink_.error(decl.range,
                            fmt::format("too many arguments: a model has at most 3 (X, Y, Z), "
                                        "'{}' would be the 4th", decl.name));
                continue;
            }
            const int axis = static_cast<int>(model_.arguments.size());
            model_.arguments.push_back(decl.name);
            if (decl.range_hi) {
                double lo = 0, hi = 0;
                bool ok = constant_of(*decl.range_hi, scope, "an argument range", hi);
                if (decl.range_lo) ok = constant_of(*decl.range_lo, scope, "an argument range", lo) && ok;
                else lo = -hi;
                if (ok && !(lo < hi)) {
                    sink_.error(decl.range,
                                fmt::format("argument range needs min < max, got {}({}, {})",
                                            decl.name, format_number(lo), format_number(hi)));
                } else if (ok) {
                    model_.ranges[axis] = AxisRange{lo, hi};
                }
            } else if (rectangle_ && axis < 2) {
                model_.ranges[axis] = axis == 0 ? AxisRange{(*rectangle_)[0], (*rectangle_)[2]}
                                                : AxisRange{(*rectangle_)[1], (*rectangle_)[3]};
            }
            Binding b;
            b.kind = Binding::Kind::Argument;
            b.name = decl.name;
            b.where = decl.range;
            b.node = graph_.argument(axis);
            scope.define(std::move(b));
        }
    }

    void lower_statement(const ast::Statement& statement, const ast::Definition& def, Scope& scope) {
        if (def.value && def.value->kind == ast::Expr::Kind::Array) {
            define_array(statement, def, scope);
            return;
        }
        if (def.value && def.value->kind == ast::Expr::Kind::Call && !scope.exact(def.value->name) &&
            lower_case(def.value->name) == "image") {
            define_image(def, scope);
            return;
        }
        const Context context =
            def.section == ast::Section::Constant ? Context::Constant : Context::Variable;
        const std::optional<double> given = context == Context::Constant && scope.top_level()
                                                ? take_constant_override(def.name) : std::nullopt;
        NodeId node = given ? graph_.constant(*given) : lower_expr(*def.value, scope, context);
        Binding b;
        b.kind = context == Context::Constant ? Binding::Kind::Constant : Binding::Kind::Variable;
        b.name = def.name;
        b.where = def.name_range;
        b.node = node;
        if (context == Context::Constant && !graph_.is_constant(node) && !poisoned_) {
            sink_.warning(def.name_range,
                          fmt::format("CONSTANT '{}' is not a finite number", def.name));
        }
        poisoned_ = false;
        if (scope.top_level() && !(ir::op_flags(graph_.node(node).op) & ir::kLeaf))
            model_.definitions.emplace_back(def.name, node);
        scope.define(std::move(b));
    }

    void define_array(const ast::Statement&, const ast::Definition& def, Scope& scope) {
        Binding b;
        b.kind = Binding::Kind::Array;
        b.name = def.name;
        b.where = def.name_range;
        if (def.section != ast::Section::Constant) {
            sink_.error(def.value->range,
                        fmt::format("array '{}' must be a CONSTANT", def.name),
                        "arrays hold compile-time numbers: CONSTANT P = [1, 2, 3];");
            b.array.assign(def.value->operands.size(), 0.0);  // keep indexing quiet: one error
            scope.define(std::move(b));
            return;
        }
        // An element that names an array splices it in, so arrays can grow in loops:
        // CONSTANT PX = [PX, X0 + R*COS(T)];
        const auto max_elements = static_cast<std::size_t>(options_.limits[LimitId::array]);
        for (const ast::ExprPtr& element : def.value->operands) {
            const Binding* array = as_array(*element, scope);
            if (b.array.size() + (array ? array->array.size() : 1) > max_elements) {
                over_limit(element->range, LimitId::array,
                           fmt::format("array '{}' would have more than {} elements", def.name,
                                       format_count(max_elements)));
                b.array.clear();
                scope.define(std::move(b));
                return;
            }
            if (array) {
                b.array.insert(b.array.end(), array->array.begin(), array->array.end());
                continue;
            }
            double v = 0;
            constant_of(*element, scope, "an array element", v);
            b.array.push_back(v);
        }
        scope.define(std::move(b));
    }

    /// CONSTANT T = IMAGE('bump.png'): a picture's grey levels as an array, row after row
    /// from the top (a height map for stdlib/perturb.fortu, fv-method.md §5.2).
    void define_image(const ast::Definition& def, Scope& scope) {
        Binding b;
        b.kind = Binding::Kind::Array;
        b.name = def.name;
        b.where = def.name_range;
        if (def.section != ast::Section::Constant) {
            sink_.error(def.value->range, fmt::format("array '{}' must be a CONSTANT", def.name),
                        "an image is read once, before evaluation: CONSTANT T = IMAGE('bump.png');");
        } else if (std::optional<ImageTable> table = read_image_argument(*def.value)) {
            b.array = std::move(table->values);
        }
        scope.define(std::move(b));
    }

    /// The table of IMAGE('file') / IMAGE_WIDTH('file'), the file found next to the script.
    std::optional<ImageTable> read_image_argument(const ast::Expr& call) {
        if (call.operands.size() != 1 || call.operands[0]->kind != ast::Expr::Kind::String) {
            sink_.error(call.range, fmt::format("{} takes one file name in quotes, e.g. {}('bump.png')",
                                                call.name, call.name));
            return std::nullopt;
        }
        const ast::Expr& file = *call.operands[0];
        std::filesystem::path path(file.name);
        if (path.is_relative() && file.range.file)
            path = std::filesystem::path(file.range.file->path()).parent_path() / path;
        std::string error;
        std::optional<ImageTable> table = loader_.load_image(path.string(), error, static_cast<std::size_t>(options_.limits[LimitId::image_pixels]));
        if (!table) {
            sink_.error(file.range, fmt::format("cannot read image '{}': {}", file.name, error));
            syntax_errors_ = true;  // stop: every use of the table would fail after this
            return std::nullopt;
        }
        const long long max_pixels = options_.limits[LimitId::image_pixels];
        if (table->values.size() > static_cast<std::size_t>(max_pixels)) {
            sink_.error(file.range, fmt::format("image '{}' is {}x{}: at most {} pixels", file.name,
                                                table->width, table->height, max_pixels),
                        "a height map costs a few operations per pixel at every point; scale it down");
            syntax_errors_ = true;
            return std::nullopt;
        }
        return table;
    }

    void lower_statement(const ast::Statement& statement, const ast::ReturnStmt& stmt, Scope& scope) {
        if (scope_depth_ > 0) {
            // A function body's RETURN is handled by call_function.
            (void)statement; (void)stmt; (void)scope;
            return;
        }
        if (return_seen_) {
            sink_.error(statement.range, "second RETURN: a script defines one function");
            sink_.note(first_return_, "the first RETURN is here");
            return;
        }
        return_seen_ = true;
        first_return_ = statement.range;
        if (model_.arguments.empty()) return;  // reported in finish()
        model_.root = lower_expr(*stmt.value, scope, Context::Variable);
    }

    void lower_statement(const ast::Statement& statement, const ast::RectangleStmt& stmt, Scope& scope) {
        std::array<double, 4> r{};
        bool ok = constant_of(*stmt.xmin, scope, "RECTANGLE", r[0]);
        ok = constant_of(*stmt.ymin, scope, "RECTANGLE", r[1]) && ok;
        ok = constant_of(*stmt.xmax, scope, "RECTANGLE", r[2]) && ok;
        ok = constant_of(*stmt.ymax, scope, "RECTANGLE", r[3]) && ok;
        if (!ok) return;
        if (!(r[0] < r[2]) || !(r[1] < r[3])) {
            sink_.error(statement.range,
                        fmt::format("RECTANGLE needs xmin < xmax and ymin < ymax, got ({}, {}, {}, {})",
                                    format_number(r[0]), format_number(r[1]),
                                    format_number(r[2]), format_number(r[3])),
                        "RECTANGLE(xmin, ymin, xmax, ymax)");
            return;
        }
        rectangle_ = r;
        // Arguments declared before RECTANGLE without a range of their own follow it too.
        for (std::size_t axis = 0; axis < std::min<std::size_t>(2, model_.arguments.size()); ++axis)
            if (!model_.ranges[axis])
                model_.ranges[axis] = axis == 0 ? AxisRange{r[0], r[2]} : AxisRange{r[1], r[3]};
    }

    void lower_statement(const ast::Statement&, const ast::RectBmpStmt& stmt, Scope& scope) {
        double size[2] = {0, 0};
        const ast::Expr* exprs[2] = {stmt.width.get(), stmt.height.get()};
        bool ok = true;
        for (int i = 0; i < 2; ++i) {
            if (!constant_of(*exprs[i], scope, "RECTBMP", size[i])) { ok = false; continue; }
            if (!(size[i] >= 1 && size[i] <= 1'000'000 && size[i] == std::floor(size[i]))) {
                sink_.error(exprs[i]->range,
                            fmt::format("RECTBMP sizes must be positive integers, got {}",
                                        format_number(size[i])));
                ok = false;
            }
        }
        if (ok) model_.raster = std::array<int, 2>{static_cast<int>(size[0]), static_cast<int>(size[1])};
    }

    void lower_statement(const ast::Statement& statement, const ast::RSystemStmt& stmt, Scope& scope) {
        switch (stmt.kind) {
            case ast::RSystemStmt::Kind::R0: alpha_ = 0.0; return;
            case ast::RSystemStmt::Kind::MinMax: alpha_ = 1.0; return;
            case ast::RSystemStmt::Kind::Alpha: {
                double a = 0;
                if (!constant_of(*stmt.alpha, scope, "ALPHA", a)) return;
                if (!(a > -1.0 && a <= 1.0)) {
                    sink_.error(stmt.alpha->range,
                                fmt::format("ALPHA must be in (-1, 1], got {}", format_number(a)));
                    return;
                }
                alpha_ = a;
                return;
            }
        }
        (void)statement;
    }

    void lower_statement(const ast::Statement&, const ast::FunctionDef& def, Scope& scope) {
        Binding b;
        b.kind = Binding::Kind::Function;
        b.name = def.name;
        b.where = def.name_range;
        b.function = &def;
        int returns = 0;
        for (const ast::Statement& s : def.body) {
            if (std::holds_alternative<ast::ReturnStmt>(s.node)) {
                if (++returns == 2)
                    sink_.error(s.range, fmt::format("second RETURN in function '{}'", def.name));
            } else if (std::holds_alternative<ast::ArgumentStmt>(s.node) ||
                       std::holds_alternative<ast::FunctionDef>(s.node) ||
                       std::holds_alternative<ast::IncludeStmt>(s.node) ||
                       std::holds_alternative<ast::RectangleStmt>(s.node) ||
                       std::holds_alternative<ast::RectBmpStmt>(s.node)) {
                sink_.error(s.range, fmt::format("not allowed inside function '{}'", def.name),
                            "a function body holds CONSTANT/VARIABLE definitions, FOR loops and one RETURN");
            }
        }
        if (returns == 0)
            sink_.error(def.name_range, fmt::format("function '{}' has no RETURN", def.name));
        scope.define(std::move(b));
    }

    void lower_statement(const ast::Statement& statement, const ast::ForStmt& loop, Scope& scope) {
        double from = 0, to = 0, step = 1;
        bool ok = constant_of(*loop.from, scope, "a FOR bound", from);
        ok = constant_of(*loop.to, scope, "a FOR bound", to) && ok;
        if (loop.step) ok = constant_of(*loop.step, scope, "a FOR step", step) && ok;
        if (!ok) return;
        if (step == 0) {
            sink_.error(loop.step->range, "FOR step must not be 0");
            return;
        }
        const double count = std::floor((to - from) / step) + 1;
        const long long max_iterations = options_.limits[LimitId::loop];
        if (count > static_cast<double>(max_iterations)) {
            sink_.error(statement.range,
                        fmt::format("FOR loop would run {} times (at most {} allowed)",
                                    format_number(count), max_iterations),
                        limit_hint(LimitId::loop, max_iterations));
            return;
        }
        for (double i = from; step > 0 ? i <= to : i >= to; i += step) {
            // Near 1E17 a step of 1 is below the spacing of doubles: I would never move.
            if (i + step == i) {
                sink_.error(loop.step ? loop.step->range : statement.range,
                            fmt::format("FOR step {} does not change {} = {}: the step is below the "
                                        "precision of numbers that large", format_number(step),
                                        loop.index, format_number(i)),
                            "use a larger step, or smaller bounds");
                syntax_errors_ = true;
                return;
            }
            Binding index;
            index.kind = Binding::Kind::Constant;
            index.name = loop.index;
            index.where = loop.index_range;
            index.node = graph_.constant(i);
            scope.define(std::move(index));
            lower_block(loop.body, scope);
            if (too_many_errors()) return;
        }
    }

    void lower_statement(const ast::Statement& statement, const ast::IncludeStmt& inc, Scope& scope) {
        const SourceFile* from = statement.range.file;
        std::vector<std::filesystem::path> candidates;
        std::filesystem::path relative(inc.path);
        if (relative.is_absolute()) {
            candidates.push_back(relative);
        } else {
            if (from) candidates.push_back(std::filesystem::path(from->path()).parent_path() / relative);
            for (const std::string& dir : options_.include_dirs) candidates.push_back(std::filesystem::path(dir) / relative);
        }
        for (const auto& candidate : candidates) {
            if (!loader_.exists(candidate.string())) continue;
            const std::string key = loader_.identity(candidate.string());
            // A file that is still being read includes itself, directly or through others:
            // reading it once more would skip its own definitions below the INCLUDE.
            const auto open = std::find_if(including_.begin(), including_.end(),
                                           [&](const IncludedFile& f) { return f.identity == key; });
            if (open != including_.end()) {
                std::string chain;
                for (auto f = open; f != including_.end(); ++f) chain += f->path + " -> ";
                sink_.error(statement.range, fmt::format("INCLUDE cycle: {}{}", chain, open->path));
                syntax_errors_ = true;  // stop: what follows would only echo it
                return;
            }
            if (included_.count(key)) return;  // each file once: includes are libraries
            std::string error;
            auto source = loader_.load_script(candidate.string(), error);
            if (!source) {
                sink_.error(statement.range, fmt::format("cannot include '{}': {}", inc.path, error));
                return;
            }
            included_.insert(key);
            sink_.retain(source);
            const int errors_before = sink_.error_count();
            ast::Script script = parse_script(*source, sink_);
            if (sink_.error_count() != errors_before) {
                syntax_errors_ = true;  // stop here, as for the main script
                return;
            }
            if (static_cast<long long>(including_.size()) >= options_.limits[LimitId::include_depth]) {
                over_limit(statement.range, LimitId::include_depth,
                           fmt::format("INCLUDE nests more than {} files deep", including_.size()));
                return;
            }
            included_scripts_.push_back(std::move(script));
            including_.push_back({key, source->path()});
            lower_block(included_scripts_.back().statements, scope);
            including_.pop_back();
            return;
        }
        std::string searched;
        for (const auto& c : candidates) {
            const std::string dir = c.parent_path().empty() ? "." : c.parent_path().string();
            searched += (searched.empty() ? "" : ", ") + dir;
        }
        sink_.error(statement.range, fmt::format("cannot find '{}' to include", inc.path),
                    fmt::format("searched: {}", searched.empty() ? "(nowhere)" : searched));
        syntax_errors_ = true;  // stop: every name the library defines would be reported unknown
    }

    // -- expressions --

    /// The array a bare name refers to, or nullptr (nothing reported).
    const Binding* as_array(const ast::Expr& e, const Scope& scope) {
        if (e.kind != ast::Expr::Kind::Name) return nullptr;
        const Binding* b = scope.exact(e.name);
        if (!b) {
            std::set<std::string> matches;
            scope.case_matches(e.name, matches);
            if (matches.size() == 1) b = resolve(e.name, e.name_range, scope);
        }
        return b && b->kind == Binding::Kind::Array ? b : nullptr;
    }

    /// Lowers `expr` and requires a compile-time number (ranges, sizes, bounds, indices).
    bool constant_of(const ast::Expr& expr, const Scope& scope, const char* what, double& value) {
        const int errors = sink_.error_count();
        const char* outer = constant_what_;
        constant_what_ = what;
        NodeId node = lower_expr(expr, scope, Context::Constant);
        constant_what_ = outer;
        if (sink_.error_count() != errors) return false;
        if (!graph_.is_constant(node)) {
            sink_.error(expr.range, fmt::format("{} must be a finite constant", what));
            return false;
        }
        value = graph_.constant_value(node);
        return true;
    }

    /// Every expression lowered costs one unit of work and one level of nesting while its
    /// operands (and the bodies of the functions it calls) are lowered: the bounds that keep
    /// a small script from hanging, exhausting memory or overflowing the stack.
    NodeId lower_expr(const ast::Expr& e, const Scope& scope, Context context) {
        if (!spend_work(e.range)) return poison();
        if (nesting_ >= options_.limits[LimitId::nesting]) {
            over_limit(e.range, LimitId::nesting,
                       fmt::format("expressions nest more than {} deep here, counting the bodies of the "
                                   "functions called", format_count(static_cast<std::uint64_t>(nesting_))));
            return poison();
        }
        ++nesting_;
        const NodeId node = lower_expr_unguarded(e, scope, context);
        --nesting_;
        if (graph_.size() > static_cast<std::size_t>(options_.limits[LimitId::nodes]))
            over_limit(e.range, LimitId::nodes,
                       fmt::format("the model has more than {} nodes after lowering this",
                                   format_count(static_cast<std::uint64_t>(options_.limits[LimitId::nodes]))));
        return node;
    }

    /// Counts one step of lowering; false (reported once) when the budget is spent.
    bool spend_work(const SourceRange& where) {
        if (++work_ <= options_.limits[LimitId::work]) return true;
        over_limit(where, LimitId::work,
                   fmt::format("compiling the script takes more than {} steps (FOR loops unroll and "
                               "functions inline; this is where the budget ran out)",
                               format_count(static_cast<std::uint64_t>(options_.limits[LimitId::work]))));
        return false;
    }

    /// Reports an exceeded budget once and stops lowering.
    void over_limit(const SourceRange& where, LimitId id, std::string message) {
        if (!syntax_errors_) sink_.error(where, std::move(message), limit_hint(id, options_.limits[id]));
        syntax_errors_ = true;
    }

    NodeId lower_expr_unguarded(const ast::Expr& e, const Scope& scope, Context context) {
        switch (e.kind) {
            case ast::Expr::Kind::Number: return graph_.constant(e.number);
            case ast::Expr::Kind::Name: return lower_name(e, scope, context);
            case ast::Expr::Kind::Unary: {
                NodeId a = lower_expr(*e.operands[0], scope, context);
                return e.unary_op == ast::UnaryOp::Plus ? a : graph_.unary(Op::Neg, a);
            }
            case ast::Expr::Kind::Binary: {
                NodeId a = lower_expr(*e.operands[0], scope, context);
                NodeId b = lower_expr(*e.operands[1], scope, context);
                switch (e.binary_op) {
                    case ast::BinaryOp::Add: return graph_.binary(Op::Add, a, b);
                    case ast::BinaryOp::Sub: return graph_.binary(Op::Sub, a, b);
                    case ast::BinaryOp::Mul: return graph_.binary(Op::Mul, a, b);
                    case ast::BinaryOp::Div: return graph_.binary(Op::Div, a, b);
                    case ast::BinaryOp::Pow: return graph_.binary(Op::Pow, a, b);
                    case ast::BinaryOp::RAnd: return graph_.binary(Op::RAnd, a, b, alpha());
                    case ast::BinaryOp::ROr: return graph_.binary(Op::ROr, a, b, alpha());
                }
                return poison();
            }
            case ast::Expr::Kind::Call: return lower_call(e, scope, context);
            case ast::Expr::Kind::String:
                sink_.error(e.range, "a quoted name is not a number",
                            "quotes name files: INCLUDE 'lib.fortu', IMAGE('bump.png'), IMAGE_WIDTH('bump.png')");
                return poison();
            case ast::Expr::Kind::Array:
                sink_.error(e.range, "an array [...] can only be the whole value of a CONSTANT");
                return poison();
        }
        return poison();
    }

    double alpha() const { return options_.rsystem ? options_.rsystem->alpha : alpha_; }

    NodeId poison() {
        poisoned_ = true;
        return graph_.constant(0.0);
    }

    /// Exact match first; else the one binding that differs only in case (with a note);
    /// several such bindings are an error. nullptr when nothing matches (nothing reported).
    const Binding* resolve(const std::string& name, const SourceRange& where, const Scope& scope) {
        if (const Binding* b = scope.exact(name)) return b;
        std::set<std::string> matches;
        scope.case_matches(name, matches);
        if (matches.empty()) return nullptr;
        if (matches.size() > 1) {
            std::string list;
            for (const std::string& m : matches) list += (list.empty() ? "'" : ", '") + m + "'";
            sink_.error(where, fmt::format("'{}' is ambiguous: it matches {} (names differ only in case)",
                                           name, list),
                        "spell the name exactly as defined");
            return &ambiguous_;
        }
        const std::string& target = *matches.begin();
        if (noted_.insert(name + '\0' + target).second) {
            sink_.note(where, fmt::format("'{}' matched '{}' (names match case-insensitively when "
                                          "nothing matches exactly)", name, target));
        }
        return scope.exact(target);
    }

    NodeId lower_name(const ast::Expr& e, const Scope& scope, Context context) {
        const Binding* b = resolve(e.name, e.name_range, scope);
        if (b == &ambiguous_) return poison();
        if (!b) {
            if (lower_case(e.name) == "pi") return graph_.constant(M_PI);
            if (find_builtin(e.name)) {
                sink_.error(e.name_range,
                            fmt::format("'{}' is a built-in function; call it as {}(...)", e.name, e.name));
                return poison();
            }
            std::string hint;
            if (model_.arguments.empty())
                hint = "no ARGUMENT is declared yet: start the script with ARGUMENT X, Y[, Z];";
            sink_.error(e.name_range, fmt::format("unknown name '{}'", e.name), hint);
            return poison();
        }
        switch (b->kind) {
            case Binding::Kind::Argument:
                if (context == Context::Constant && constant_what_) {
                    sink_.error(e.name_range, fmt::format("{} must be a constant; argument '{}' varies "
                                                          "from point to point", constant_what_, e.name));
                    return poison();
                }
                if (context == Context::Constant) {
                    sink_.error(e.name_range,
                                fmt::format("argument '{}' cannot be used in a CONSTANT", e.name),
                                "a CONSTANT is a number fixed before evaluation; define it as a VARIABLE");
                    return poison();
                }
                return b->node;
            case Binding::Kind::Constant:
                return b->node;
            case Binding::Kind::Variable:
                if (context == Context::Constant && constant_what_ && !graph_.is_constant(b->node)) {
                    sink_.error(e.name_range, fmt::format("{} must be a constant; variable '{}' varies "
                                                          "from point to point", constant_what_, e.name));
                    return poison();
                }
                if (context == Context::Constant && !graph_.is_constant(b->node)) {
                    sink_.error(e.name_range,
                                fmt::format("variable '{}' varies over the space and cannot be used "
                                            "in a CONSTANT", e.name),
                                "define this value as a VARIABLE");
                    return poison();
                }
                return b->node;
            case Binding::Kind::Array:
                sink_.error(e.name_range,
                            fmt::format("'{}' is an array; index it as {}(I) or use SIZE({})",
                                        e.name, e.name, e.name));
                return poison();
            case Binding::Kind::Function:
                sink_.error(e.name_range,
                            fmt::format("'{}' is a function; call it as {}(...)", e.name, e.name));
                return poison();
        }
        return poison();
    }

    NodeId lower_call(const ast::Expr& e, const Scope& scope, Context context) {
        const int argc = static_cast<int>(e.operands.size());
        // User definitions first (exact, then case-insensitive), then built-ins.
        const Binding* b = resolve(e.name, e.name_range, scope);
        if (b == &ambiguous_) return poison();
        if (b && b->kind == Binding::Kind::Array) return index_array(e, *b, scope);
        if (b && b->kind == Binding::Kind::Function) return call_function(e, *b, scope, context);
        if (!b && (lower_case(e.name) == "image_width" || lower_case(e.name) == "image_height")) {
            const std::optional<ImageTable> table = read_image_argument(e);
            if (!table) return poison();
            return graph_.constant(lower_case(e.name) == "image_width" ? table->width : table->height);
        }
        if (!b && lower_case(e.name) == "image") {
            sink_.error(e.range, "IMAGE('...') is a whole table, not a number",
                        "define it as CONSTANT T = IMAGE('bump.png'); and use T(I) or BILINEAR");
            return poison();
        }
        const Builtin* builtin = find_builtin(e.name, argc);
        if (b && !builtin) {
            sink_.error(e.name_range,
                        fmt::format("'{}' is {} {}, not a function or an array", e.name,
                                    b->kind == Binding::Kind::Argument ? "an" : "a", kind_word(b->kind)));
            return poison();
        }
        if (!builtin) {
            sink_.error(e.name_range, fmt::format("unknown function '{}'", e.name));
            return poison();
        }
        if (!builtin->takes(argc)) {
            const auto [min_args, max_args] = argument_counts(builtin->name);
            std::string expected =
                max_args < 0 ? fmt::format("at least {}", plural(min_args, "argument"))
                : min_args == max_args ? plural(min_args, "argument")
                : fmt::format("{} or {} arguments", min_args, max_args);
            sink_.error(e.range, fmt::format("{} takes {}, got {}", builtin->name, expected, argc));
            return poison();
        }
        if (builtin->op == Op::Const) {  // SIZE(array)
            const ast::Expr& arg = *e.operands[0];
            const Binding* array = as_array(arg, scope);
            if (!array) {
                sink_.error(arg.range, "SIZE takes the name of an array");
                return poison();
            }
            return graph_.constant(static_cast<double>(array->array.size()));
        }
        std::vector<NodeId> args;
        for (const ast::ExprPtr& operand : e.operands) args.push_back(lower_expr(*operand, scope, context));
        const Op op = builtin->op;
        if (ir::op_arity(op) == 1) return graph_.unary(op, args[0]);
        if (ir::op_arity(op) == 3) return graph_.make(op, args);
        const double imm = (ir::op_flags(op) & ir::kROperation) ? alpha() : 0.0;
        NodeId acc = args[0];
        for (int i = 1; i < argc; ++i) acc = graph_.binary(op, acc, args[i], imm);
        return acc;
    }

    NodeId index_array(const ast::Expr& e, const Binding& array, const Scope& scope) {
        if (e.operands.size() != 1) {
            sink_.error(e.range, fmt::format("array '{}' takes one index, got {}", array.name,
                                             e.operands.size()));
            return poison();
        }
        double index = 0;
        if (!constant_of(*e.operands[0], scope, "an array index", index)) return poison();
        const double size = static_cast<double>(array.array.size());
        if (index != std::floor(index)) {
            sink_.error(e.operands[0]->range, fmt::format("index {} of array '{}' is not a whole number",
                                                          format_number(index), array.name));
            return poison();
        }
        if (index < 1 || index > size) {
            sink_.error(e.operands[0]->range,
                        array.array.empty()
                            ? fmt::format("array '{}' is empty", array.name)
                            : fmt::format("index {} is out of range for array '{}' (1 to {})",
                                          format_number(index), array.name, array.array.size()));
            return poison();
        }
        return graph_.constant(array.array[static_cast<std::size_t>(index) - 1]);
    }

    NodeId call_function(const ast::Expr& e, const Binding& b, const Scope& scope, Context context) {
        const ast::FunctionDef& def = *b.function;
        if (e.operands.size() != def.params.size()) {
            sink_.error(e.range, fmt::format("function '{}' takes {}, got {}", def.name,
                                             plural(static_cast<int>(def.params.size()), "argument"),
                                             e.operands.size()));
            return poison();
        }
        if (std::find(active_calls_.begin(), active_calls_.end(), &def) != active_calls_.end()) {
            sink_.error(e.name_range, fmt::format("function '{}' calls itself", def.name),
                        "functions are inlined; repeat work with a FOR loop instead");
            return poison();
        }
        Scope local(b.written_at);   // the body sees the names where it is written, not here
        // The call's identity: the function as written here, the argument nodes (arrays by
        // their elements), the R-system and the context, all that the result depends on.
        std::string call_key = call_identity(b, context);
        for (std::size_t i = 0; i < def.params.size(); ++i) {
            Binding p;
            p.kind = Binding::Kind::Variable;
            p.name = def.params[i];
            p.where = def.param_ranges[i];
            if (const Binding* array = as_array(*e.operands[i], scope)) {  // arrays pass whole
                p.kind = Binding::Kind::Array;
                p.array = array->array;
                append_bytes(call_key, 'A', p.array.size());
                call_key.append(reinterpret_cast<const char*>(p.array.data()), p.array.size() * sizeof(double));
                local.define(std::move(p));
                continue;
            }
            p.node = lower_expr(*e.operands[i], scope, context);
            if (graph_.is_constant(p.node)) p.kind = Binding::Kind::Constant;
            append_bytes(call_key, 'N', p.node);
            local.define(std::move(p));
        }
        if (const auto seen = inlined_.find(call_key); seen != inlined_.end()) return seen->second;
        const int errors_before = sink_.error_count();
        active_calls_.push_back(&def);
        ++scope_depth_;
        NodeId result = poison();
        for (const ast::Statement& s : def.body) {
            if (auto* ret = std::get_if<ast::ReturnStmt>(&s.node)) {
                result = lower_expr(*ret->value, local, context);
                break;
            }
            std::visit([&](const auto& node) { lower_statement(s, node, local); }, s.node);
        }
        --scope_depth_;
        active_calls_.pop_back();
        // A body that changes the R-system has an effect beyond its result: lower it each time.
        if (sink_.error_count() == errors_before && !changes_rsystem(def.body)) inlined_.emplace(std::move(call_key), result);
        return result;
    }

    std::string call_identity(const Binding& function, Context context) const {
        std::string key;
        append_bytes(key, 'F', function.function);
        append_bytes(key, 'S', function.written_at.scope);
        append_bytes(key, 'V', function.written_at.version);
        append_bytes(key, 'R', alpha());
        append_bytes(key, 'C', context);
        return key;
    }

    template <class T>
    static void append_bytes(std::string& key, char tag, const T& value) {
        key += tag;
        key.append(reinterpret_cast<const char*>(&value), sizeof value);
    }

    static bool changes_rsystem(const std::vector<ast::Statement>& body) {
        for (const ast::Statement& s : body) {
            if (std::holds_alternative<ast::RSystemStmt>(s.node)) return true;
            if (const auto* loop = std::get_if<ast::ForStmt>(&s.node); loop && changes_rsystem(loop->body)) return true;
        }
        return false;
    }

    // -- the end --

    /// The value CompileOptions::constants gives `name`, the first time it is asked for.
    std::optional<double> take_constant_override(const std::string& name) {
        for (std::size_t i = 0; i < options_.constants.size(); ++i)
            if (lower_case(options_.constants[i].first) == lower_case(name) && !overridden_.count(i)) {
                overridden_.insert(i);
                return options_.constants[i].second;
            }
        return std::nullopt;
    }

    void finish(const SourceFile& source, const ast::Script& script) {
        for (std::size_t i = 0; i < options_.constants.size(); ++i)
            if (!overridden_.count(i))
                sink_.error({}, fmt::format("cannot set '{}': the script has no top-level CONSTANT of that name",
                                            options_.constants[i].first));
        if (model_.arguments.empty()) {
            sink_.error(script.statements.empty() ? at_start(source) : script.statements.front().range,
                        "script declares no ARGUMENT",
                        "declare the coordinates first, e.g. ARGUMENT X, Y;");
            return;
        }
        if (!return_seen_) sink_.error(at_end(source), "script has no RETURN",
                                       "end the script with RETURN expression;");
    }

    bool too_many_errors() const { return syntax_errors_ || sink_.error_count() >= kMaxErrors; }

    static SourceRange at_start(const SourceFile& source) { return {&source, {1, 1}, {1, 1}}; }
    static SourceRange at_end(const SourceFile& source) {
        int line = std::max(1, source.line_count());
        while (line > 1 && source.line(line).find_first_not_of(" \t\r") == std::string_view::npos) --line;
        int col = static_cast<int>(source.line(line).size()) + 1;
        return {&source, {line, col}, {line, col}};
    }

    static constexpr int kMaxErrors = 50;

    const CompileOptions& options_;
    const SourceLoader& loader_;
    DiagnosticSink& sink_;
    Model& model_;
    ir::Graph& graph_;
    Scope global_;
    std::set<std::size_t> overridden_;   ///< CompileOptions::constants entries already applied
    Binding ambiguous_;
    double alpha_ = 0.0;
    bool return_seen_ = false;
    bool warned_after_return_ = false;
    bool poisoned_ = false;
    bool syntax_errors_ = false;
    const char* constant_what_ = nullptr;  ///< what constant_of is evaluating, for its messages
    int scope_depth_ = 0;
    SourceRange first_return_;
    std::optional<std::array<double, 4>> rectangle_;
    std::set<std::string> noted_;
    std::set<std::string> included_;
    /// The files being read, the main script first, each INCLUDE'd by the one before it.
    struct IncludedFile {
        std::string identity;
        std::string path;
    };
    std::vector<IncludedFile> including_;
    std::vector<ast::Script> included_scripts_;
    std::vector<const ast::FunctionDef*> active_calls_;
    long long work_ = 0;      ///< lowering steps so far (LimitId::work)
    long long nesting_ = 0;   ///< lower_expr calls open (LimitId::nesting)
    /// Inlined calls by function and argument nodes: a call seen before is its result again
    /// (hash-consing the call, not only its result), so F(A) = G(A) + G(A+1) nested 40 deep
    /// lowers each level once, not 2^40 times.
    std::unordered_map<std::string, NodeId> inlined_;
};

}  // namespace

std::string RSystem::name() const {
    if (alpha == 0.0) return "R0";
    if (alpha == 1.0) return "MINMAX";
    return fmt::format("ALPHA={}", alpha);
}

std::optional<RSystem> parse_rsystem(const std::string& text) {
    const std::string t = lower_case(text);
    if (t == "r0") return RSystem{0.0};
    if (t == "minmax" || t == "r1") return RSystem{1.0};
    if (t.rfind("alpha=", 0) == 0) {
        try {
            std::size_t used = 0;
            double a = std::stod(t.substr(6), &used);
            if (used == t.size() - 6 && a > -1.0 && a <= 1.0) return RSystem{a};
        } catch (...) {
        }
    }
    return std::nullopt;
}

std::optional<Model> compile(std::shared_ptr<const SourceFile> source, const CompileOptions& options,
                             DiagnosticSink& sink) {
    Model model;
    const int errors_before = sink.error_count();
    run_on_large_stack([&] {
        Lowerer lowerer(options, sink, model);
        lowerer.run(source);
    });
    apply_domain_comment(*source, model, sink);
    if (sink.error_count() != errors_before || model.root == ir::kNoNode) return std::nullopt;
    return model;
}

}  // namespace fortu
