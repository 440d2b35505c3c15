// --export-mesh: the flag's mesh of every frame as an OBJ file, written atomically.

#include "runtime/mesh_export.h"

#include <charconv>
#include <cstdio>

#include "engine/files/atomic_file.h"

namespace engine {

namespace {

// `value` as printf's %.17g would write it in the C locale (to_chars is exact and locale-free).
void appendNumber(std::string& out, double value) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, 17);
    out.append(buf, r.ptr);
}

}  // namespace

std::string objText(const std::string& comment, const cloth::Points& x, const std::vector<cloth::Triangle>& triangles) {
    std::string out;
    out.reserve(comment.size() + 3 + std::size_t(x.cols()) * 64 + triangles.size() * 24);
    out += "# ";
    out += comment;
    out += '\n';
    for (Eigen::Index p = 0; p < x.cols(); ++p) {
        out += 'v';
        for (int k = 0; k < 3; ++k) {
            out += ' ';
            appendNumber(out, x(k, p));
        }
        out += '\n';
    }
    char face[48];
    for (const cloth::Triangle& t : triangles) {
        const int n = std::snprintf(face, sizeof face, "f %ld %ld %ld\n", long(t[0]) + 1, long(t[1]) + 1, long(t[2]) + 1);
        out.append(face, std::size_t(n));
    }
    return out;
}

std::string MeshExport::meshPath(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "flag_%06d.obj", frame);
    return dir + "/" + name;
}

void MeshExport::write(int frame, const std::string& comment, const cloth::Points& x,
                       const std::vector<cloth::Triangle>& triangles) {
    if (!error_.empty()) return;
    std::string error;
    if (writeFileAtomically(meshPath(dir_, frame), objText(comment, x, triangles), &error)) ++written_;
    else error_ = error;
}

}  // namespace engine
