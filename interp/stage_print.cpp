// interp/stage_print.cpp — the tape and hoisting printers behind `fortu ir --stage`.
#include "interp/stage_print.hpp"

#include "interp/hoist.hpp"
#include "interp/ir_print.hpp"
#include "interp/voxel_engine.hpp"

#include <fmt/format.h>

namespace fortu {

std::optional<IrStage> parse_ir_stage(std::string_view name) {
    if (name == "lower") return IrStage::Lower;
    if (name == "tape") return IrStage::Tape;
    if (name == "hoist") return IrStage::Hoist;
    return std::nullopt;
}

std::string print_tape(const Tape& tape, const std::vector<std::string>& arguments, const TapeNaming& naming) {
    std::string out = fmt::format("; {} operation{}, {} slots\n", tape.code.size(), tape.code.size() == 1 ? "" : "s", tape.slot_count);
    for (auto [slot, axis] : tape.arguments)
        out += fmt::format("s{} = arg {}\n", slot,
                           axis < static_cast<int>(arguments.size()) ? arguments[axis] : std::to_string(axis));
    for (auto [slot, which] : tape.inputs) out += fmt::format("s{} = {} {}\n", slot, naming.input, which);
    for (auto [slot, value] : tape.constants) out += fmt::format("s{} = const {}\n", slot, value);
    for (std::size_t i = 0; i < tape.code.size(); ++i) {
        const Instruction& ins = tape.code[i];
        std::string line = fmt::format("s{} = {}", ins.out, ir::op_name(ins.op));
        for (int k = 0; k < ir::op_arity(ins.op); ++k) {
            if (!((ins.constant_operands >> k) & 1u)) {
                line += fmt::format(" s{}", ins.in[k]);
                continue;
            }
            std::string operand = fmt::format("{}", ins.constant[k]);
            for (const UniformUse& use : tape.uniform_uses)
                if (use.instruction == i && use.operand == static_cast<uint32_t>(k))
                    operand = fmt::format("{}[{}]", naming.uniform, use.uniform);
            line += ' ' + operand;
        }
        if (ir::op_flags(ins.op) & ir::kROperation) line += fmt::format(" alpha={}", ins.imm);
        out += line + '\n';
    }
    if (naming.output.empty() && tape.outputs.size() == 1) return out + fmt::format("return s{}\n", tape.outputs[0]);
    for (std::size_t k = 0; k < tape.outputs.size(); ++k)
        out += fmt::format("{} {} = s{}\n", naming.output, k, tape.outputs[k]);
    return out;
}

std::string print_stage(const Model& model, const std::string& title, IrStage stage) {
    if (stage == IrStage::Lower) return print_ir(model, title);
    if (stage == IrStage::Tape)
        return fmt::format("; {}\n; tape (no hoisting)\n", title) +
               print_tape(compile_tape(model.graph, model.root), model.arguments);
    const HoistPlan plan = plan_hoisting(model.graph, {model.root}, {});
    const Tape columns = compile_tape(model.graph, TapeSpec{plan.column_nodes, {}, {}});
    const Tape rows = compile_tape(model.graph, TapeSpec{plan.row_nodes, {}, {}});
    const Tape points = compile_tape(model.graph, TapeSpec{{model.root}, plan.column_nodes, plan.row_nodes});
    std::string out = fmt::format("; {}\n; hoisted on grids of {}+ columns: {} operations per column, {} per row, "
                                  "{} per point\n",
                                  title, kMinHoistColumns, columns.code.size(), rows.code.size(), points.code.size());
    out += "; once per grid column (X only): the column values column 0..\n";
    out += print_tape(columns, model.arguments, {"in", "uniform", "column"});
    out += "; once per grid row (no X): the row values row 0..\n";
    out += print_tape(rows, model.arguments, {"in", "uniform", "row"});
    out += "; at every point: column values as lane arrays, row values as immediates\n";
    out += print_tape(points, model.arguments, {"column", "row", ""});
    return out;
}

}  // namespace fortu
