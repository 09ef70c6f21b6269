// cli/python/errors.cpp — FortuError, Diagnostic, and UsageError as ValueError.
#include "cli/python/errors.hpp"

#include "cli/option_table.hpp"

#include <pybind11/stl.h>

namespace py = pybind11;

namespace fortu::python {
namespace {

py::object& fortu_error_type() {
    // Set once at import and never destroyed: a static py::object would be released after
    // the interpreter is gone, at process exit.
    static py::object* type = new py::object();
    return *type;
}

const char* severity_name(Severity s) {
    return s == Severity::Error ? "error" : s == Severity::Warning ? "warning" : "note";
}

}  // namespace

std::vector<DiagnosticView> diagnostic_views(const std::vector<Diagnostic>& diagnostics) {
    std::vector<DiagnosticView> views;
    for (const Diagnostic& d : diagnostics) {
        DiagnosticView v;
        v.severity = severity_name(d.severity);
        if (d.range.file) {
            v.file = d.range.file->path();
            v.line = d.range.begin.line;
            v.column = d.range.begin.column;
            v.end_line = d.range.end.line;
            v.end_column = d.range.end.column;
        }
        v.message = d.message;
        if (!d.hint.empty()) v.notes.push_back(d.hint);
        v.text = render(d);
        views.push_back(std::move(v));
    }
    return views;
}

void register_errors(py::module_& m) {
    py::class_<DiagnosticView>(m, "Diagnostic", "One diagnostic of a model: where, what, and the notes that follow it.")
        .def_readonly("severity", &DiagnosticView::severity, "'error', 'warning' or 'note'")
        .def_readonly("file", &DiagnosticView::file, "the script's path ('<string>' for text; '' without a location)")
        .def_readonly("line", &DiagnosticView::line, "1-based line (0 without a location)")
        .def_readonly("column", &DiagnosticView::column, "1-based byte column")
        .def_readonly("end_line", &DiagnosticView::end_line)
        .def_readonly("end_column", &DiagnosticView::end_column)
        .def_readonly("message", &DiagnosticView::message)
        .def_readonly("notes", &DiagnosticView::notes, "the advice lines (`note: ...`)")
        .def_readonly("text", &DiagnosticView::text, "rendered as the command line prints it: location, line, caret, notes")
        .def("__str__", [](const DiagnosticView& d) { return d.text; })
        .def("__repr__", [](const DiagnosticView& d) {
            return "<fortu.Diagnostic " + d.severity + " " + d.file + ":" + std::to_string(d.line) + ":" +
                   std::to_string(d.column) + ": " + d.message + ">";
        });
    fortu_error_type() = py::reinterpret_steal<py::object>(
        PyErr_NewExceptionWithDoc("fortu.FortuError",
                                  "A model that does not compile. str(e) is what the fortu command prints; "
                                  "e.diagnostics the Diagnostic objects.",
                                  PyExc_Exception, nullptr));
    m.attr("FortuError") = fortu_error_type();
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const UsageError& e) {
            std::string message = e.what();
            if (message.rfind("--", 0) == 0) message.erase(0, 2);   // `size: ...`, the keyword's name
            PyErr_SetString(PyExc_ValueError, message.c_str());
        }
    });
}

void raise_fortu_error(const std::vector<Diagnostic>& diagnostics) {
    std::string message;
    for (const Diagnostic& d : diagnostics)
        if (d.severity != Severity::Note) message += render(d);
    py::object error = fortu_error_type()(message);
    error.attr("diagnostics") = py::cast(diagnostic_views(diagnostics));
    PyErr_SetObject(fortu_error_type().ptr(), error.ptr());
    throw py::error_already_set();
}

}  // namespace fortu::python
