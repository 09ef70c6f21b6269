// cli/repl/repl_commands.hpp — what `fortu repl` does with one complete input: a `:command`, or
// FORTU text handed to the Session (statements join the model, a bare expression is
// evaluated at the probe point). Kept apart from the input loop so it knows no terminal
// except through ReplIo.
#pragma once

#include "cli/slice_choice.hpp"
#include "interp/engine.hpp"
#include "interp/session.hpp"
#include "interp/shaded_view.hpp"

#include <array>
#include <atomic>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>

namespace fortu {

/// Where a Repl writes and what it knows of the terminal.
struct ReplIo {
    std::ostream& out;
    std::ostream& err;
    bool colour = false;                          ///< :show in truecolour half blocks
    std::function<std::pair<int, int>()> terminal_size;   ///< columns, rows
    std::atomic<bool>* interrupt = nullptr;       ///< set by SIGINT; cancels an evaluation
};

/// One REPL: the session, the engine and probe point chosen, the last evaluation.
class Repl {
public:
    Repl(Session& session, ReplIo io);

    /// Runs one input (a command line, or FORTU text of one or more lines). Returns false
    /// for :quit. Errors are reported and the session goes on.
    bool handle(const std::string& input);
    /// True once any input was rejected (a scripted session then exits with status 1).
    bool had_error() const { return had_error_; }

    /// :load FILE (also `fortu repl MODEL.fortu`): the file's statements join the session.
    void load(const std::string& path);

    /// :help
    static std::string help_text();

    /// What Tab completes to in FORTU text: the session's names.
    std::vector<std::string> names() const { return session_.names(); }

private:
    bool command(const std::string& line);
    void fortu_text(const std::string& text);
    void error(const std::string& message);
    bool need_model();
    std::optional<std::string> classic_refusal(const Engine& engine, double points) const;
    std::optional<Field> evaluate(const Grid& grid);
    /// The session's cube as a shaded view of `width` x `height` pixels; none if interrupted.
    std::optional<SurfaceImage> shaded_view(const ViewDirection& view, int width, int height);

    /// What :show and :render draw of a 3D model: a plane (--slice) or a shaded view (--view,
    /// --up; a picture's default), as `fortu run` does.
    struct PictureChoice {
        std::optional<SliceChoice> slice;
        ViewDirection view{45, 35.264389682754654};
        bool view_given = false;
    };
    /// Reads --slice S, --view V and --up A from `args`; nullopt (reported) when malformed.
    std::optional<PictureChoice> picture_choice(const std::string& command, const std::vector<std::string>& args);
    /// The grid of the plane `slice` names, `nodes` along its longer side (0: as :size says).
    Grid plane_grid(const SliceChoice& slice, const std::vector<int>& size);

    void eval(const std::vector<std::string>& args);
    void show(const std::vector<std::string>& args);
    void render(const std::string& path, const std::vector<std::string>& args);
    void domain(const std::vector<std::string>& args);
    void size(const std::vector<std::string>& args);
    void time();
    void save(const std::string& path);

    Session& session_;
    ReplIo io_;
    const Engine* engine_ = &default_engine();
    std::array<double, 3> probe_{0, 0, 0};
    std::optional<EvalReport> last_;
    bool had_error_ = false;
};

}  // namespace fortu
