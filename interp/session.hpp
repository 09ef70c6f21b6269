// interp/session.hpp — the incremental model behind `fortu repl`: statements typed one at a
// time accumulate into a script; re-defining a name replaces its definition in place, so
// everything defined after it from that name follows (spreadsheet-like, issue 6).
//
// Why a script and not a live scope: FORTU's meaning is sequential (spec §2), and compile()
// already checks and lowers a whole script in one pass with hash-consing, so re-lowering the
// accumulated statements after each change is both exact and cheap (lowering is linear in the
// text). What is expensive is evaluating grids, so evaluation is incremental: the session
// keeps the grid values of the model and of every definition it evaluated, under the
// structural hash of their sub-DAG, and the voxel engine reads those values instead of
// computing the definitions again (NodeValues::known). After `CONSTANT R = 0.3` only what
// depends on R is recomputed; an unchanged model (or one changed back) is not evaluated at all.
#pragma once

#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "interp/engine.hpp"
#include "interp/model.hpp"

#include <array>
#include <cstdint>
#include <list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// What submit() made of one input.
struct SubmitResult {
    enum class Kind {
        Empty,        ///< only blanks or comments
        Statements,   ///< definitions etc., accepted into the session
        Expression,   ///< a bare expression: `model` holds it as its RETURN
        Error,        ///< rejected; the session is unchanged
    };
    Kind kind = Kind::Empty;
    /// Rendered diagnostics (errors when rejected; warnings about the input otherwise),
    /// located in the text as typed.
    std::string diagnostics;
    /// Kind::Expression: the session's definitions with the expression as the model.
    std::optional<Model> model;
    /// Kind::Statements: one line per statement, `defined R`, `replaced R`, `model set`...
    std::vector<std::string> changes;
};

/// How the last grid evaluation went, for `:time`.
struct EvalReport {
    bool reused = false;             ///< the model's values were kept from before: nothing was evaluated
    bool cancelled = false;          ///< interrupted (the field is incomplete and nothing was kept)
    std::size_t operations = 0;      ///< operations reachable from the model's root
    std::size_t computed_operations = 0;  ///< of which evaluated this time
    std::vector<std::string> reused_definitions;  ///< definitions whose kept values were read instead
    std::size_t kept_definitions = 0;   ///< definitions whose values were kept for next time
    double seconds = 0.0;
    std::string engine = "voxel";     ///< the engine's name
    Grid grid;
};

/// The statements of one REPL session and the model they compile to. Until ARGUMENT is
/// typed the definitions are checked as if `ARGUMENT X, Y` had been, and until RETURN
/// against a constant model, so each line gets its diagnostics as it is typed.
class Session {
public:
    /// `include_dirs`: searched by INCLUDE after a loaded file's own folder (the stdlib).
    explicit Session(std::vector<std::string> include_dirs);

    /// Parses `text` (from `origin`: `<input>` or a file's path) as FORTU statements, or,
    /// when it is not statements but parses as one expression, as a bare expression. Accepted
    /// statements join the session (re-definitions in place); rejected input leaves it as it was.
    SubmitResult submit(const std::string& text, const std::string& origin);

    /// Forgets every statement and setting.
    void reset();

    /// True once a RETURN was accepted.
    bool has_model() const { return model_.has_value(); }
    const Model& model() const { return *model_; }

    /// `:rsystem`: wins over RSYSTEM statements, as --rsystem does; recompiles.
    void set_rsystem(std::optional<RSystem> rsystem);
    const std::optional<RSystem>& rsystem() const { return rsystem_; }
    /// `:domain`: per axis overrides of the script's ranges (nullopt: the script's).
    void set_domain(std::array<std::optional<AxisRange>, 3> domain) { domain_ = domain; }
    const std::array<std::optional<AxisRange>, 3>& domain() const { return domain_; }
    /// `:size`: node counts per axis (empty: the script's RECTBMP, else 256² / 64³).
    void set_size(std::vector<int> size) { size_ = std::move(size); }
    const std::vector<int>& size() const { return size_; }

    /// The names the session defines (arguments, definitions, FUNCTIONs), in order, unique.
    std::vector<std::string> names() const;

    /// The grid `fortu run` would sample the saved script on (domain and size applied; one
    /// size number is the nodes along the longest axis, with square cells, grid_size.hpp).
    Grid grid() const;
    /// A grid over the same domain with `cols`×`rows` nodes (3D: the middle Z slice only).
    Grid grid_with_nodes(int cols, int rows) const;

    /// Samples the model on `grid`, reusing the kept values of the model, or (voxel engine)
    /// (engines with known_and_kept) of the definitions it uses, on this grid. `report` says
    /// what was reused.
    Field evaluate(const Grid& grid, const Engine& engine, const EvalOptions& options, EvalReport& report);

    /// A valid .fortu script of the session: domain and size as argument ranges and RECTBMP,
    /// `:rsystem` as RSYSTEM, then the statements in order. `fortu run` on it samples the
    /// same grid as grid().
    std::string script() const;

private:
    /// One accepted statement: where its text is (a slice of what was typed or loaded, so
    /// diagnostics point there) and the keyword that must precede it when re-assembled.
    struct Entry {
        enum class Kind { RSystem, Rectangle, RectBmp, Argument, Definition, Function, Include, For, Return };
        Kind kind = Kind::Definition;
        std::string name;      ///< Definition/Function: its name; Include: the path
        std::string keyword;   ///< put before the slice: CONSTANT, VARIABLE, RETURN or nothing
        std::shared_ptr<const SourceFile> file;
        SourcePos begin, end;  ///< the slice, half-open
        bool inferred = false; ///< a bare `name = expr` of this input, its section inferred
    };
    struct Assembled;

    std::optional<SubmitResult> try_compile(const std::vector<Entry>& entries, const Entry* probe,
                                            const SourceFile* typed, std::optional<Model>& out) const;
    Assembled assemble(const std::vector<Entry>& entries, const Entry* probe) const;

    std::vector<std::string> include_dirs_;
    std::vector<Entry> entries_;
    std::optional<Model> model_;
    std::optional<RSystem> rsystem_;
    std::array<std::optional<AxisRange>, 3> domain_;
    std::vector<int> size_;
    std::string section_ = "VARIABLE";   ///< the section in force for `name = expr`

    /// Values of one node (a definition, or the model) on one grid, kept for reuse.
    struct KeptValues {
        uint64_t key = 0;            ///< structural hash of the node, the grid, the precision
        std::vector<double> values;
    };
    const std::vector<double>* find_kept(uint64_t key);
    void keep(uint64_t key, std::vector<double> values);
    std::list<KeptValues> kept_;     ///< most recently used first, at most kKeptBytes of values
};

/// The structural hash of every node reachable from `root` (indexed by node id; 0 for
/// unreachable ones): equal for equal sub-expressions, whichever graph they live in.
std::vector<uint64_t> structural_hashes(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
