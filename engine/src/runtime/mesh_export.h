#pragma once
// --export-mesh DIR: the flag's mesh after every frame as DIR/flag_NNNNNN.obj, a Wavefront OBJ in
// world coordinates: a comment line (the scene, the frame, the simulated time, the solver), a
// `v x y z` per particle with 17 significant digits (it reads back to the same doubles), then an
// `f a b c` (1-based) per triangle of the flag's model. Each file is written to a temporary name
// in DIR and renamed, so DIR never holds half a mesh. The first failed write is kept, the frames
// after it are not written (as the PNG frames), and Runtime::finish reports it.

#include <string>
#include <vector>

#include "cloth/model.h"

namespace engine {

// The OBJ text: `# comment`, the vertices, the faces.
std::string objText(const std::string& comment, const cloth::Points& x, const std::vector<cloth::Triangle>& triangles);

class MeshExport {
public:
    explicit MeshExport(std::string dir) : dir_(std::move(dir)) {}

    // Writes frame `frame`'s mesh; nothing after a failed write.
    void write(int frame, const std::string& comment, const cloth::Points& x,
               const std::vector<cloth::Triangle>& triangles);
    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }  // "DIR/flag_NNNNNN.obj: cannot write: why"
    int written() const { return written_; }
    const std::string& dir() const { return dir_; }

    static std::string meshPath(const std::string& dir, int frame);  // DIR/flag_NNNNNN.obj

private:
    std::string dir_;
    std::string error_;
    int written_ = 0;
};

}  // namespace engine
