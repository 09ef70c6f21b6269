// interp/vm_import.cpp — the .vm reader: one SSA line at a time, names resolved to the
// nodes made so far (Graph::make shares and folds them, as for FORTU scripts).
#include "interp/vm_import.hpp"

#include "interp/written_r_operations.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <string>
#include <unordered_map>
#include <vector>

namespace fortu {
namespace {

struct VmOp {
    std::string_view name;
    ir::Op op;
};

// The ops of the format (ops.def's FORTU_VM_OP lines); var-* and const are handled apart.
constexpr VmOp kVmOps[] = {
#define FORTU_VM_OP(spelling, name) {spelling, ir::Op::name},
#include "interp/ir/ops.def"
};

/// The hint of an unknown operation: every operation of the format, in its order.
std::string known_operations() {
    std::string text = "known: var-x var-y var-z const";
    for (const VmOp& op : kVmOps) text += fmt::format(" {}", op.name);
    return text;
}

struct Token {
    std::string_view text;
    int column;   ///< 1-based byte column
};

std::vector<Token> split_line(std::string_view line) {
    std::vector<Token> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        if (i >= line.size() || line[i] == '#') break;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' && line[i] != '#') ++i;
        tokens.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
    }
    return tokens;
}

}  // namespace

bool is_vm_path(std::string_view path) {
    if (path.size() < 3) return false;
    std::string_view ext = path.substr(path.size() - 3);
    return ext[0] == '.' && (ext[1] == 'v' || ext[1] == 'V') && (ext[2] == 'm' || ext[2] == 'M');
}

std::optional<Model> import_vm(std::shared_ptr<const SourceFile> source, DiagnosticSink& sink) {
    Model model;
    std::unordered_map<std::string_view, ir::NodeId> names;
    ir::NodeId last = ir::kNoNode;
    bool uses_z = false;
    const int errors_before = sink.error_count();

    for (int line_no = 1; line_no <= source->line_count(); ++line_no) {
        const std::string_view line = source->line(line_no);
        const std::vector<Token> tokens = split_line(line);
        if (tokens.empty()) continue;
        auto range = [&](const Token& t) {
            return SourceRange{source.get(), {line_no, t.column}, {line_no, t.column + static_cast<int>(t.text.size())}};
        };
        auto line_end = [&]() {
            const Token& t = tokens.back();
            const int col = t.column + static_cast<int>(t.text.size());
            return SourceRange{source.get(), {line_no, col}, {line_no, col}};
        };
        if (tokens.size() < 2) {
            sink.error(line_end(), fmt::format("expected an operation after '{}'", tokens[0].text),
                       "each line is: NAME OP ARGS...");
            continue;
        }
        const Token& name = tokens[0];
        const Token& op = tokens[1];
        if (names.count(name.text)) {
            sink.error(range(name), fmt::format("'{}' is defined twice", name.text),
                       "every value of the SSA format has its own name");
            continue;
        }
        auto expect_count = [&](std::size_t operands) {
            if (tokens.size() == 2 + operands) return true;
            if (tokens.size() > 2 + operands)
                sink.error(range(tokens[2 + operands]),
                           fmt::format("'{}' takes {} operand{}", op.text, operands, operands == 1 ? "" : "s"));
            else
                sink.error(line_end(), fmt::format("'{}' takes {} operand{}, got {}", op.text, operands,
                                                   operands == 1 ? "" : "s", tokens.size() - 2));
            return false;
        };
        ir::NodeId id = ir::kNoNode;
        if (op.text == "var-x" || op.text == "var-y" || op.text == "var-z") {
            if (!expect_count(0)) continue;
            const int axis = op.text[4] - 'x';
            uses_z = uses_z || axis == 2;
            id = model.graph.argument(axis);
        } else if (op.text == "const") {
            if (!expect_count(1)) continue;
            const Token& number = tokens[2];
            double value = 0;
            auto [ptr, ec] = std::from_chars(number.text.data(), number.text.data() + number.text.size(), value);
            if (ec != std::errc() || ptr != number.text.data() + number.text.size() || !std::isfinite(value)) {
                sink.error(range(number), fmt::format("'{}' is not a finite number", number.text));
                continue;
            }
            id = model.graph.constant(value);
        } else {
            const VmOp* found = nullptr;
            for (const VmOp& candidate : kVmOps)
                if (candidate.name == op.text) found = &candidate;
            if (!found) {
                sink.error(range(op), fmt::format("unknown operation '{}'", op.text), known_operations());
                continue;
            }
            const int arity = ir::op_arity(found->op);
            if (!expect_count(arity)) continue;
            ir::NodeId args[ir::kMaxArity] = {ir::kNoNode, ir::kNoNode, ir::kNoNode};
            bool ok = true;
            for (int k = 0; k < arity; ++k) {
                auto it = names.find(tokens[2 + k].text);
                if (it == names.end()) {
                    sink.error(range(tokens[2 + k]), fmt::format("unknown name '{}'", tokens[2 + k].text),
                               "a value must be defined on an earlier line");
                    ok = false;
                    break;
                }
                args[k] = it->second;
            }
            if (!ok) continue;
            // R0 written out (a + b ∓ sqrt(a² + b²)) becomes the R-operation, the same IEEE
            // operations in the same order, which the pruned renderers can prune.
            ir::NodeId a, b;
            if (arity == 2 && written_r0(model.graph, found->op, args[0], args[1], a, b))
                id = r0_operation(model.graph, found->op, a, b);
            else
                id = model.graph.make(found->op, std::span<const ir::NodeId>(args, arity));
        }
        names.emplace(name.text, id);
        last = id;
    }
    if (sink.error_count() > errors_before) return std::nullopt;
    if (last == ir::kNoNode) {
        sink.error(SourceRange{source.get(), {1, 1}, {1, 1}}, "the model has no values",
                   "a .vm model is lines NAME OP ARGS...; the last one is the result");
        return std::nullopt;
    }
    model.root = model.graph.unary(ir::Op::Neg, last);
    model.arguments = uses_z ? std::vector<std::string>{"X", "Y", "Z"} : std::vector<std::string>{"X", "Y"};
    for (std::size_t a = 0; a < model.arguments.size(); ++a) model.ranges[a] = AxisRange{-1.0, 1.0};
    return model;
}

}  // namespace fortu
