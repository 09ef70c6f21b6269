// tests/unit/grammar_diagnostic_test.cpp — SourceFile (lines, loading) and the diagnostic
// renderer: exact text, caret line included.
#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace fortu;

namespace {

SourceRange at(const SourceFile& file, int line, int column, int end_line, int end_column) {
    return SourceRange{&file, SourcePos{line, column}, SourcePos{end_line, end_column}};
}

Diagnostic error_at(SourceRange range, std::string message, std::string hint = {}) {
    return Diagnostic{Severity::Error, range, std::move(message), std::move(hint)};
}

}  // namespace

TEST_CASE("SourceFile splits lines at newlines and tolerates CRLF") {
    SUBCASE("plain") {
        SourceFile file("a.fortu", "ARGUMENT X;\nRETURN X;\n");
        CHECK(file.line_count() == 2);
        CHECK(file.line(1) == "ARGUMENT X;");
        CHECK(file.line(2) == "RETURN X;");
        CHECK(file.line(0) == "");
        CHECK(file.line(3) == "");
    }
    SUBCASE("final line without newline counts") {
        SourceFile file("a.fortu", "a\nb");
        CHECK(file.line_count() == 2);
        CHECK(file.line(2) == "b");
    }
    SUBCASE("CRLF: line() drops the CR") {
        SourceFile file("a.fortu", "a = 1\r\n\r\nb\r\n");
        CHECK(file.line_count() == 3);
        CHECK(file.line(1) == "a = 1");
        CHECK(file.line(2) == "");
        CHECK(file.line(3) == "b");
    }
    SUBCASE("a lone CR (classic Mac OS) ends a line; CRLF is one line end") {
        SourceFile file("a.fortu", "a = 1\rb\r\rc\r\nd");
        CHECK(file.line_count() == 5);
        CHECK(file.line(1) == "a = 1");
        CHECK(file.line(2) == "b");
        CHECK(file.line(3) == "");
        CHECK(file.line(4) == "c");
        CHECK(file.line(5) == "d");
    }
    SUBCASE("empty file has one empty line") {
        SourceFile file("a.fortu", "");
        CHECK(file.line_count() == 1);
        CHECK(file.line(1) == "");
    }
    SUBCASE("bytes are kept verbatim") {
        const std::string text("// \xcf\xf0\xe8\0x\n", 9);
        SourceFile file("a.fortu", text);
        CHECK(file.text() == text);
        CHECK(file.line(1) == std::string_view(text.data(), 8));
    }
}

TEST_CASE("SourceFile::load reads binary-exact and reports failures") {
    const fortu::test::ScratchDir scratch;
    const std::filesystem::path& dir = scratch.path;
    const std::string path = (dir / "bytes.fortu").string();
    const std::string bytes("ARGUMENT X;\r\n// \xcf\xf0\xe8\xec\xe5\xf0\n\0\xff RETURN X;", 33);
    {
        std::ofstream out(path, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    std::string error = "stale";
    auto file = SourceFile::load(path, error);
    REQUIRE(file != nullptr);
    CHECK(error.empty());
    CHECK(file->path() == path);
    CHECK(file->text() == bytes);
    CHECK(file->line(1) == "ARGUMENT X;");

    SUBCASE("missing file") {
        const std::string missing = (dir / "missing.fortu").string();
        CHECK(SourceFile::load(missing, error) == nullptr);
        CHECK(error == "cannot read '" + missing + "': No such file or directory");
    }
    SUBCASE("directory") {
        CHECK(SourceFile::load(dir.string(), error) == nullptr);
        CHECK(error == "cannot read '" + dir.string() + "': is a directory");
    }
}

TEST_CASE("render: location, source line, caret under the range, note") {
    std::string text;
    for (int i = 1; i < 12; ++i) text += "CONSTANT C" + std::to_string(i) + " = 1;\n";
    text += "VARIABLE W = Y2 + 1;\n";
    SourceFile file("model.fortu", text);
    CHECK(render(error_at(at(file, 12, 14, 12, 16), "unknown name 'Y2'")) ==
          "model.fortu:12:14: error: unknown name 'Y2'\n"
          "VARIABLE W = Y2 + 1;\n"
          "             ^~\n");
    CHECK(render(error_at(at(file, 12, 14, 12, 16), "unknown name 'Y2'", "did you mean 'C2'?")) ==
          "model.fortu:12:14: error: unknown name 'Y2'\n"
          "VARIABLE W = Y2 + 1;\n"
          "             ^~\n"
          "note: did you mean 'C2'?\n");
}

TEST_CASE("render: severities") {
    SourceFile file("m.fortu", "x = 1\n");
    CHECK(render(Diagnostic{Severity::Warning, at(file, 1, 1, 1, 2), "unused 'x'", {}}) ==
          "m.fortu:1:1: warning: unused 'x'\nx = 1\n^\n");
    CHECK(render(Diagnostic{Severity::Note, at(file, 1, 5, 1, 6), "defined here", {}}) ==
          "m.fortu:1:5: note: defined here\nx = 1\n    ^\n");
}

TEST_CASE("render: caret line details") {
    SUBCASE("empty range: a lone caret") {
        SourceFile file("m.fortu", "W = 1 +\n");
        CHECK(render(error_at(at(file, 1, 8, 1, 8), "unexpected end of line")) ==
              "m.fortu:1:8: error: unexpected end of line\nW = 1 +\n       ^\n");
    }
    SUBCASE("a range spanning lines: a lone caret") {
        SourceFile file("m.fortu", "W = (1 +\n  2)\n");
        CHECK(render(error_at(at(file, 1, 5, 2, 5), "bad")) ==
              "m.fortu:1:5: error: bad\nW = (1 +\n    ^\n");
    }
    SUBCASE("tabs are kept so the caret lines up") {
        SourceFile file("m.fortu", "\tW =\t(a +\n");
        CHECK(render(error_at(at(file, 1, 6, 1, 7), "x")) ==
              "m.fortu:1:6: error: x\n\tW =\t(a +\n\t   \t^\n");
    }
    SUBCASE("UTF-8 continuation bytes add no space") {
        SourceFile file("m.fortu", "W = \xd1\x88\xd0\xb0 + @\n");   // "W = ша + @"
        CHECK(render(error_at(at(file, 1, 12, 1, 13), "unexpected character '@'")) ==
              "m.fortu:1:12: error: unexpected character '@'\n"
              "W = \xd1\x88\xd0\xb0 + @\n"
              "         ^\n");
        // A range over a two-byte character is one cell wide.
        CHECK(render(error_at(at(file, 1, 5, 1, 9), "x")) ==
              "m.fortu:1:5: error: x\nW = \xd1\x88\xd0\xb0 + @\n    ^~\n");
    }
    SUBCASE("past the end of the line: just after the last character") {
        SourceFile file("m.fortu", "RETURN\n");
        CHECK(render(error_at(at(file, 1, 40, 1, 41), "eof")) ==
              "m.fortu:1:40: error: eof\nRETURN\n      ^\n");
        // A range running past the end is cut at the end of the line.
        CHECK(render(error_at(at(file, 1, 4, 1, 40), "x")) ==
              "m.fortu:1:4: error: x\nRETURN\n   ^~~\n");
    }
    SUBCASE("CRLF line: the CR is not shown") {
        SourceFile file("m.fortu", "W = 1 2\r\n");
        CHECK(render(error_at(at(file, 1, 7, 1, 8), "x")) == "m.fortu:1:7: error: x\nW = 1 2\n      ^\n");
    }
}

TEST_CASE("render: a diagnostic without a file") {
    CHECK(render(Diagnostic{Severity::Error, {}, "too many errors, giving up", {}}) ==
          "error: too many errors, giving up\n");
    CHECK(render(Diagnostic{Severity::Error, {}, "bad size '0x0'", "write --size 800x800"}) ==
          "error: bad size '0x0'\nnote: write --size 800x800\n");
}

TEST_CASE("DiagnosticSink collects in order and counts errors only") {
    SourceFile file("m.fortu", "x = 1\n");
    DiagnosticSink sink;
    CHECK_FALSE(sink.has_errors());
    sink.warning(at(file, 1, 1, 1, 2), "w");
    CHECK_FALSE(sink.has_errors());
    sink.error(at(file, 1, 5, 1, 6), "e", "h");
    sink.note(at(file, 1, 1, 1, 2), "n");
    sink.report(Diagnostic{Severity::Error, {}, "plain", {}});
    CHECK(sink.error_count() == 2);
    CHECK(sink.has_errors());
    REQUIRE(sink.diagnostics().size() == 4);
    CHECK(sink.diagnostics()[1].hint == "h");
    CHECK(sink.render_all() ==
          "m.fortu:1:1: warning: w\nx = 1\n^\n"
          "m.fortu:1:5: error: e\nx = 1\n    ^\nnote: h\n"
          "m.fortu:1:1: note: n\nx = 1\n^\n"
          "error: plain\n");
    sink.clear();
    CHECK(sink.error_count() == 0);
    CHECK(sink.diagnostics().empty());
}

TEST_CASE("a long source line is shown as a window around the caret") {
    const std::string text = "W = " + std::string(300, 'A') + " @ " + std::string(300, 'B') + ";";
    fortu::SourceFile file("long.fortu", text);
    fortu::Diagnostic d{fortu::Severity::Error, {&file, {1, 306}, {1, 307}}, "unexpected character '@'", ""};
    const std::string window = std::string(text.begin() + 245, text.begin() + 365);
    CHECK(fortu::render(d) == "long.fortu:1:306: error: unexpected character '@'\n"
                              "..." + window + "...\n" + std::string(63, ' ') + "^\n");
}
