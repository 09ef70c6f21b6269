// runtime/mesh_io.cpp — STL, OBJ and PLY writers and readers.
#include "runtime/mesh_io.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_path.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;

Vec face_normal(const Mesh& m, const std::array<uint32_t, 3>& t) {
    const Vec& a = m.vertices[t[0]];
    const Vec& b = m.vertices[t[1]];
    const Vec& c = m.vertices[t[2]];
    const Vec u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    Vec n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double len = std::hypot(n[0], n[1], n[2]);
    if (len > 0)
        for (double& x : n) x /= len;
    return n;
}

template <class T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts only (as the npy writer)
    out.append(bytes, sizeof(T));
}

std::runtime_error read_error(const std::string& path, const std::string& reason) {
    return std::runtime_error(fmt::format("cannot read mesh '{}': {}", path, reason));
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw read_error(path, "cannot open it");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

template <class T>
T get(const std::string& bytes, std::size_t& at, const std::string& path) {
    if (at + sizeof(T) > bytes.size()) throw read_error(path, "the file ends early");
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}

/// Triangle soup to an indexed mesh: equal positions become one vertex.
Mesh weld(const std::vector<Vec>& corners) {
    Mesh m;
    std::map<Vec, uint32_t> index;
    for (std::size_t i = 0; i + 2 < corners.size(); i += 3) {
        std::array<uint32_t, 3> t{};
        for (int k = 0; k < 3; ++k) {
            auto [it, fresh] = index.emplace(corners[i + k], static_cast<uint32_t>(m.vertices.size()));
            if (fresh) m.vertices.push_back(corners[i + k]);
            t[k] = it->second;
        }
        m.triangles.push_back(t);
    }
    return m;
}

Mesh read_stl(const std::string& path) {
    const std::string bytes = slurp(path);
    std::vector<Vec> corners;
    if (bytes.size() >= 84) {
        std::size_t at = 80;
        const auto count = get<uint32_t>(bytes, at, path);
        if (bytes.size() == 84 + std::size_t(count) * 50) {
            corners.reserve(std::size_t(count) * 3);
            for (uint32_t t = 0; t < count; ++t) {
                at += 12;  // the facet normal
                for (int k = 0; k < 3; ++k) {
                    Vec p{};
                    for (double& x : p) x = get<float>(bytes, at, path);
                    corners.push_back(p);
                }
                at += 2;
            }
            return weld(corners);
        }
    }
    if (bytes.rfind("solid", 0) != 0) throw read_error(path, "neither binary nor ASCII STL");
    std::istringstream in(bytes);
    std::string word;
    while (in >> word)
        if (word == "vertex") {
            Vec p{};
            if (!(in >> p[0] >> p[1] >> p[2])) throw read_error(path, "a vertex without three numbers");
            corners.push_back(p);
        }
    if (corners.size() % 3 != 0) throw read_error(path, "a facet without three vertices");
    return weld(corners);
}

Mesh read_obj(const std::string& path) {
    std::istringstream in(slurp(path));
    Mesh m;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        if (kind == "v") {
            Vec p{};
            words >> p[0] >> p[1] >> p[2];
            m.vertices.push_back(p);
        } else if (kind == "f") {
            std::array<uint32_t, 3> t{};
            for (uint32_t& v : t) {
                std::string ref;
                if (!(words >> ref)) throw read_error(path, "a face without three vertices");
                const long k = std::stol(ref);
                if (k < 1 || std::size_t(k) > m.vertices.size()) throw read_error(path, "a face refers to no vertex");
                v = static_cast<uint32_t>(k - 1);
            }
            m.triangles.push_back(t);
        }
    }
    return m;
}

Mesh read_ply(const std::string& path) {
    const std::string bytes = slurp(path);
    const std::size_t end = bytes.find("end_header\n");
    if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) throw read_error(path, "not a PLY file");
    if (bytes.find("format binary_little_endian 1.0") > end) throw read_error(path, "not binary little-endian PLY");
    std::istringstream header(bytes.substr(0, end));
    std::string line;
    std::size_t vertices = 0, faces = 0;
    int vertex_doubles = 0;
    std::string element;
    while (std::getline(header, line)) {
        std::istringstream words(line);
        std::string w, type, name;
        words >> w;
        if (w == "element") {
            words >> element;
            (element == "vertex" ? vertices : faces) = std::stoul((words >> name, name));
        } else if (w == "property" && element == "vertex") {
            words >> type;
            if (type != "double") throw read_error(path, "vertex properties must be double");
            ++vertex_doubles;
        }
    }
    if (vertex_doubles < 3) throw read_error(path, "vertices without x, y, z");
    std::size_t at = end + 11;
    Mesh m;
    for (std::size_t v = 0; v < vertices; ++v) {
        Vec p{};
        for (int k = 0; k < vertex_doubles; ++k) {
            const double x = get<double>(bytes, at, path);
            if (k < 3) p[k] = x;
        }
        m.vertices.push_back(p);
    }
    for (std::size_t f = 0; f < faces; ++f) {
        if (get<uint8_t>(bytes, at, path) != 3) throw read_error(path, "a face that is not a triangle");
        std::array<uint32_t, 3> t{};
        for (uint32_t& v : t) {
            v = get<uint32_t>(bytes, at, path);
            if (v >= vertices) throw read_error(path, "a face refers to no vertex");
        }
        m.triangles.push_back(t);
    }
    return m;
}

}  // namespace

void write_stl(const Mesh& mesh, const std::string& path, const OutputOptions& options) {
    write_file_atomically(path, [&](OutputFile& file) {
        std::string out;
        if (options.ascii) {
            out = "solid fortu\n";
            // Three numbers as printf's " %.9g" each (std::to_chars: fmt's precision path took
            // most of the write).
            auto numbers = [&out](const Vec& v) {
                for (double x : v) {
                    char text[32] = {' '};
                    out.append(text, std::to_chars(text + 1, text + sizeof text, x, std::chars_format::general, 9).ptr);
                }
                out += '\n';
            };
            for (const auto& t : mesh.triangles) {
                out += "facet normal";
                numbers(face_normal(mesh, t));
                out += " outer loop\n";
                for (uint32_t v : t) {
                    out += "  vertex";
                    numbers(mesh.vertices[v]);
                }
                out += " endloop\nendfacet\n";
                if (out.size() > (1u << 20)) file.write(out), out.clear();
            }
            out += "endsolid fortu\n";
            file.write(out);
            return;
        }
        out.assign(80, ' ');
        out.replace(0, 24, "fortu binary STL mesh   ");
        put<uint32_t>(out, static_cast<uint32_t>(mesh.triangles.size()));
        for (const auto& t : mesh.triangles) {
            for (double x : face_normal(mesh, t)) put<float>(out, static_cast<float>(x));
            for (uint32_t v : t)
                for (double x : mesh.vertices[v]) put<float>(out, static_cast<float>(x));
            put<uint16_t>(out, 0);
            if (out.size() > (1u << 20)) file.write(out), out.clear();
        }
        file.write(out);
    });
}

void write_obj(const Mesh& mesh, const std::string& path, const OutputOptions&) {
    write_file_atomically(path, [&](OutputFile& file) {
        std::string out = fmt::format("# fortu mesh: {} vertices, {} triangles\n", mesh.vertices.size(),
                                      mesh.triangles.size());
        auto flush = [&] {
            if (out.size() > (1u << 20)) file.write(out), out.clear();
        };
        for (const Vec& p : mesh.vertices) {
            out += fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
            flush();
        }
        const bool normals = mesh.normals.size() == mesh.vertices.size();
        if (normals)
            for (const Vec& n : mesh.normals) {
                out += fmt::format("vn {} {} {}\n", n[0], n[1], n[2]);
                flush();
            }
        for (const auto& t : mesh.triangles) {
            if (normals) out += fmt::format("f {0}//{0} {1}//{1} {2}//{2}\n", t[0] + 1, t[1] + 1, t[2] + 1);
            else out += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
            flush();
        }
        file.write(out);
    });
}

void write_ply(const Mesh& mesh, const std::string& path, const OutputOptions&) {
    write_file_atomically(path, [&](OutputFile& file) {
        const bool normals = mesh.normals.size() == mesh.vertices.size();
        std::string out = fmt::format("ply\nformat binary_little_endian 1.0\ncomment fortu mesh\nelement vertex {}\n"
                                      "property double x\nproperty double y\nproperty double z\n{}"
                                      "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
                                      mesh.vertices.size(),
                                      normals ? "property double nx\nproperty double ny\nproperty double nz\n" : "",
                                      mesh.triangles.size());
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
            for (double x : mesh.vertices[v]) put<double>(out, x);
            if (normals)
                for (double x : mesh.normals[v]) put<double>(out, x);
            if (out.size() > (1u << 20)) file.write(out), out.clear();
        }
        for (const auto& t : mesh.triangles) {
            put<uint8_t>(out, 3);
            for (uint32_t v : t) put<uint32_t>(out, v);
            if (out.size() > (1u << 20)) file.write(out), out.clear();
        }
        file.write(out);
    });
}

Mesh read_mesh(const std::string& path) {
    const std::string ext = path_extension(path);
    if (ext == "stl") return read_stl(path);
    if (ext == "obj") return read_obj(path);
    if (ext == "ply") return read_ply(path);
    throw read_error(path, "not a mesh format (.stl, .obj, .ply)");
}

}  // namespace fortu
