#include "engine/render/renderer.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "render/gl_api.h"
#include "render/msaa_target.h"
#include "render/frame_upload.h"

namespace engine {

namespace {

const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
uniform mat4 uModel, uViewProj, uLightViewProj;
out vec3 vWorld; out vec3 vNormal; out vec2 vUv; out vec4 vLight;
void main() {
    vec4 world = uModel * vec4(aPosition, 1.0);
    vWorld = world.xyz;
    vNormal = mat3(uModel) * aNormal;  // rigid transforms and uniform scales only
    vUv = aUv;
    vLight = uLightViewProj * world;
    gl_Position = uViewProj * world;
}
)";

const char* kMeshFragment = R"(#version 330 core
in vec3 vWorld; in vec3 vNormal; in vec2 vUv; in vec4 vLight;
uniform vec3 uColor, uSunDir, uSunColor, uSky, uHorizon, uBounce, uEye;
uniform float uAmbient, uFogDensity;
uniform int uUseTexture, uDoubleSided, uShadowSize;
uniform sampler2D uTexture;
uniform sampler2DShadow uShadow;
out vec4 fragColor;
float shadow(vec3 n) {
    vec3 p = vLight.xyz / vLight.w * 0.5 + 0.5;
    if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) return 1.0;
    float bias = 0.0015 + 0.003 * (1.0 - abs(dot(n, -uSunDir)));
    // Four taps half a texel apart; each is a bilinear 2x2 comparison: a soft 3x3 footprint for
    // a third of the cost of nine taps (llvmpipe shades on the CPU).
    vec2 o = vec2(0.5 / float(uShadowSize));
    float lit = texture(uShadow, vec3(p.xy + vec2(-o.x, -o.y), p.z - bias))
              + texture(uShadow, vec3(p.xy + vec2(o.x, -o.y), p.z - bias))
              + texture(uShadow, vec3(p.xy + vec2(-o.x, o.y), p.z - bias))
              + texture(uShadow, vec3(p.xy + vec2(o.x, o.y), p.z - bias));
    return lit * 0.25;
}
// Lighting happens in linear space (colour uniforms arrive linearized by the CPU, textures are
// sRGB and sample linear), and the result is encoded here rather than by GL_FRAMEBUFFER_SRGB,
// whose effect depends on the context (an OSMesa buffer and an X11 window disagree).
vec3 toDisplay(vec3 c) { return pow(max(c, vec3(0.0)), vec3(1.0 / 2.2)); }
void main() {
    vec3 n = normalize(vNormal);
    if (uDoubleSided == 1 && !gl_FrontFacing) n = -n;
    vec3 base = uColor;
    if (uUseTexture == 1) base *= texture(uTexture, vUv).rgb;  // sRGB texture: sampled linear
    vec3 l = -uSunDir;
    float diffuse = max(dot(n, l), 0.0) * (uShadowSize > 0 ? shadow(n) : 1.0);
    vec3 ambient = mix(uBounce, uSky, 0.5 + 0.5 * n.y) * uAmbient;
    vec3 v = normalize(uEye - vWorld);
    float spec = pow(max(dot(n, normalize(l + v)), 0.0), 32.0) * 0.15 * diffuse;
    vec3 color = toDisplay(base * (ambient + diffuse * uSunColor) + spec * uSunColor);
    float fog = 1.0 - exp(-uFogDensity * length(uEye - vWorld));
    fragColor = vec4(mix(color, uHorizon, fog), 1.0);
}
)";

const char* kShadowVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uModel, uLightViewProj;
void main() { gl_Position = uLightViewProj * uModel * vec4(aPosition, 1.0); }
)";

const char* kShadowFragment = R"(#version 330 core
void main() {}
)";

// A full-screen triangle; the view direction per pixel picks the sky colour.
const char* kSkyVertex = R"(#version 330 core
out vec2 vNdc;
void main() {
    vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
    vNdc = p;
    gl_Position = vec4(p, 1.0, 1.0);  // on the far plane: drawn last, only where nothing else is
}
)";

const char* kSkyFragment = R"(#version 330 core
in vec2 vNdc;
uniform mat4 uInvViewProj;
uniform vec3 uSky, uHorizon, uBounce;
out vec4 fragColor;
void main() {
    vec4 a = uInvViewProj * vec4(vNdc, -1.0, 1.0), b = uInvViewProj * vec4(vNdc, 1.0, 1.0);
    vec3 dir = normalize(b.xyz / b.w - a.xyz / a.w);
    vec3 c = dir.y > 0.0 ? mix(uHorizon, uSky, pow(dir.y, 0.6)) : mix(uHorizon, uBounce, min(-dir.y * 4.0, 1.0));
    fragColor = vec4(c, 1.0);
}
)";

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up) {
    const Eigen::Vector3f f = (target - eye).normalized();
    const Eigen::Vector3f s = f.cross(up).normalized();
    const Eigen::Vector3f u = s.cross(f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Eigen::Matrix4f perspective(float fovYDeg, float aspect, float n, float f) {
    const float t = 1.0f / std::tan(fovYDeg * 3.14159265f / 360.0f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    m(0, 0) = t / aspect;
    m(1, 1) = t;
    m(2, 2) = (f + n) / (n - f);
    m(2, 3) = 2 * f * n / (n - f);
    m(3, 2) = -1;
    return m;
}

Eigen::Matrix4f ortho(float halfW, float halfH, float n, float f) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m(0, 0) = 1 / halfW;
    m(1, 1) = 1 / halfH;
    m(2, 2) = -2 / (f - n);
    m(2, 3) = -(f + n) / (f - n);
    return m;
}

}  // namespace

struct Renderer::Impl {
    gl::Api gl;
    GLContext* context = nullptr;
    GLuint meshProgram = 0, shadowProgram = 0, skyProgram = 0, skyVao = 0;
    GLuint shadowFbo = 0, shadowTexture = 0;
    int shadowSize = 0;
    std::unique_ptr<MsaaTarget> msaa;  // null: the main pass draws straight into framebuffer 0
    bool post = false;                 // the frame read back gets the post pass (frame_aa.h)
    FrameUpload shown;                 // in a window, the post pass's frame put back on screen
    std::string glRenderer;
    void chooseAntiAliasing(const GLContext& context, AntiAliasing aa, int samples);
    struct Mesh {
        GLuint vao = 0, vbo = 0, ebo = 0;
        GLsizei indexCount = 0;
        std::size_t vertexCount = 0;
        std::vector<float> uvs;  // dynamic meshes keep theirs for re-upload
        Material material;
        bool dynamic = false;
    };
    std::vector<Mesh> meshes;
    std::vector<GLuint> textures;
    std::vector<float> interleaved;

    GLuint link(const char* vs, const char* fs) { return gl::linkProgram(gl, vs, fs); }
    GLint loc(GLuint program, const char* name) { return gl.GetUniformLocation(program, name); }
    void setMat(GLuint p, const char* name, const Eigen::Matrix4f& m) {
        gl.UniformMatrix4fv(loc(p, name), 1, GL_FALSE, m.data());
    }
    void setVec(GLuint p, const char* name, const Eigen::Vector3f& v) { gl.Uniform3fv(loc(p, name), 1, v.data()); }
    // Display (sRGB-like, gamma 2.2) colour to linear, for the lighting uniforms.
    void setLinear(GLuint p, const char* name, const Eigen::Vector3f& v) {
        const Eigen::Vector3f lin(std::pow(v.x(), 2.2f), std::pow(v.y(), 2.2f), std::pow(v.z(), 2.2f));
        setVec(p, name, lin);
    }

    // Interleaves position, normal, uv (8 floats per vertex) and uploads it.
    void upload(Mesh& m, const float* pos, const float* nrm, const float* uv, GLenum usage, bool reallocate) {
        interleaved.resize(m.vertexCount * 8);
        for (std::size_t i = 0; i < m.vertexCount; ++i) {
            float* d = &interleaved[8 * i];
            for (int k = 0; k < 3; ++k) d[k] = pos[3 * i + k];
            for (int k = 0; k < 3; ++k) d[3 + k] = nrm ? nrm[3 * i + k] : 0.0f;
            d[6] = uv ? uv[2 * i] : 0.0f;
            d[7] = uv ? uv[2 * i + 1] : 0.0f;
        }
        gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo);
        const auto bytes = static_cast<GLsizeiptr>(interleaved.size() * sizeof(float));
        if (reallocate) gl.BufferData(GL_ARRAY_BUFFER, bytes, interleaved.data(), usage);
        else gl.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, interleaved.data());
    }

    int create(std::size_t vertexCount, const std::vector<std::uint32_t>& indices, const Material& material,
               bool dynamic) {
        Mesh m;
        m.vertexCount = vertexCount;
        m.indexCount = static_cast<GLsizei>(indices.size());
        m.material = material;
        m.dynamic = dynamic;
        gl.GenVertexArrays(1, &m.vao);
        gl.BindVertexArray(m.vao);
        gl.GenBuffers(1, &m.vbo);
        gl.GenBuffers(1, &m.ebo);
        gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo);
        gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertexCount * 8 * sizeof(float)), nullptr,
                      dynamic ? GL_DYNAMIC_DRAW : GL_STATIC_DRAW);
        gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ebo);
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * 4), indices.data(),
                      GL_STATIC_DRAW);
        const GLsizei stride = 8 * sizeof(float);
        gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(0));
        gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
        gl.VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(6 * sizeof(float)));
        for (GLuint a = 0; a < 3; ++a) gl.EnableVertexAttribArray(a);
        gl.BindVertexArray(0);
        meshes.push_back(m);
        return static_cast<int>(meshes.size()) - 1;
    }

    void drawItems(const std::vector<DrawItem>& items, GLuint program, bool shadowPass) {
        for (const DrawItem& item : items) {
            if (shadowPass && !item.castsShadow) continue;
            const Mesh& m = meshes.at(static_cast<std::size_t>(item.mesh));
            setMat(program, "uModel", item.model);
            if (!shadowPass) {
                setLinear(program, "uColor", m.material.color);
                const bool textured = m.material.texture >= 0;
                gl.Uniform1i(loc(program, "uUseTexture"), textured ? 1 : 0);
                gl.Uniform1i(loc(program, "uDoubleSided"), m.material.doubleSided ? 1 : 0);
                gl.ActiveTexture(GL_TEXTURE0);
                gl.BindTexture(GL_TEXTURE_2D, textured ? textures.at(static_cast<std::size_t>(m.material.texture)) : 0);
                if (m.material.doubleSided) gl.Disable(GL_CULL_FACE);
                else gl.Enable(GL_CULL_FACE);
            }
            gl.BindVertexArray(m.vao);
            gl.DrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr);
        }
        gl.BindVertexArray(0);
    }
};

// Auto resolved from the renderer's name, then the target of the mode made; a mode the context
// cannot offer falls back to none, with a note.
void Renderer::Impl::chooseAntiAliasing(const GLContext& context, AntiAliasing aa, int samples) {
    const GLubyte* name = gl.GetString(GL_RENDERER);
    glRenderer = name ? reinterpret_cast<const char*>(name) : "";
    if (aa == AntiAliasing::Auto)
        aa = glRenderer.find("llvmpipe") != std::string::npos || glRenderer.find("softpipe") != std::string::npos
                 ? AntiAliasing::Post
                 : AntiAliasing::Msaa;
    post = aa == AntiAliasing::Post;
    if (aa != AntiAliasing::Msaa || samples < 2) return;
    msaa = std::make_unique<MsaaTarget>();
    std::string why;
    if (!msaa->create(gl, context.width(), context.height(), samples, &why)) {
        msaa.reset();
        std::fprintf(stderr, "flagsim: note: no anti-aliasing: %s\n", why.c_str());
    }
}

Renderer::Renderer(GLContext& context, int shadowMapSize, AntiAliasing aa, int msaaSamples)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.context = &context;
    std::string error;
    if (!gl::load(m.gl, context.procAddress(), &error)) throw std::runtime_error(error);
    m.meshProgram = m.link(kMeshVertex, kMeshFragment);
    m.shadowProgram = m.link(kShadowVertex, kShadowFragment);
    m.skyProgram = m.link(kSkyVertex, kSkyFragment);
    m.gl.GenVertexArrays(1, &m.skyVao);  // core profile: a VAO even for attribute-less drawing
    m.shadowSize = shadowMapSize;
    if (shadowMapSize > 0) {
        auto& gl = m.gl;
        gl.GenTextures(1, &m.shadowTexture);
        gl.BindTexture(GL_TEXTURE_2D, m.shadowTexture);
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, shadowMapSize, shadowMapSize, 0,
                      GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        gl.GenFramebuffers(1, &m.shadowFbo);
        gl.BindFramebuffer(GL_FRAMEBUFFER, m.shadowFbo);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, m.shadowTexture, 0);
        gl.DrawBuffer(GL_NONE);
        gl.ReadBuffer(GL_NONE);
        if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("the shadow-map framebuffer is incomplete");
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    m.chooseAntiAliasing(context, aa, msaaSamples);
}

AntiAliasing Renderer::antiAliasing() const {
    return impl_->msaa ? AntiAliasing::Msaa : impl_->post ? AntiAliasing::Post : AntiAliasing::Off;
}

const std::string& Renderer::glRenderer() const { return impl_->glRenderer; }

Renderer::~Renderer() {
    Impl& m = *impl_;
    auto& gl = m.gl;
    if (!gl.DeleteBuffers) return;
    for (auto& mesh : m.meshes) {
        gl.DeleteBuffers(1, &mesh.vbo);
        gl.DeleteBuffers(1, &mesh.ebo);
        gl.DeleteVertexArrays(1, &mesh.vao);
    }
    if (!m.textures.empty()) gl.DeleteTextures(static_cast<GLsizei>(m.textures.size()), m.textures.data());
    if (m.shadowFbo) gl.DeleteFramebuffers(1, &m.shadowFbo);
    if (m.shadowTexture) gl.DeleteTextures(1, &m.shadowTexture);
    gl.DeleteVertexArrays(1, &m.skyVao);
    gl.DeleteProgram(m.meshProgram);
    gl.DeleteProgram(m.shadowProgram);
    gl.DeleteProgram(m.skyProgram);
}

int Renderer::addTexture(const std::vector<std::uint8_t>& rgba, int width, int height) {
    auto& gl = impl_->gl;
    GLuint t = 0;
    gl.GenTextures(1, &t);
    gl.BindTexture(GL_TEXTURE_2D, t);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    gl.GenerateMipmap(GL_TEXTURE_2D);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    impl_->textures.push_back(t);
    return static_cast<int>(impl_->textures.size()) - 1;
}

int Renderer::addMesh(const MeshData& mesh, const Material& material) {
    std::vector<float> normals = mesh.normals;
    if (normals.size() != mesh.positions.size()) computeSmoothNormals(mesh.positions, mesh.indices, normals);
    const bool hasUv = mesh.uvs.size() == mesh.vertexCount() * 2;
    const int id = impl_->create(mesh.vertexCount(), mesh.indices, material, false);
    impl_->upload(impl_->meshes[id], mesh.positions.data(), normals.data(), hasUv ? mesh.uvs.data() : nullptr,
                  GL_STATIC_DRAW, true);
    return id;
}

int Renderer::addDynamicMesh(std::size_t vertexCount, const std::vector<std::uint32_t>& indices,
                             const std::vector<float>& uvs, const Material& material) {
    const int id = impl_->create(vertexCount, indices, material, true);
    impl_->meshes[id].uvs = uvs;
    return id;
}

void Renderer::updateDynamicMesh(int mesh, const std::vector<float>& positions, const std::vector<float>& normals) {
    Impl::Mesh& m = impl_->meshes.at(static_cast<std::size_t>(mesh));
    impl_->upload(m, positions.data(), normals.data(), m.uvs.empty() ? nullptr : m.uvs.data(), GL_DYNAMIC_DRAW,
                  false);
}

void Renderer::render(const Camera& camera, const Lighting& light, const std::vector<DrawItem>& items) {
    Impl& m = *impl_;
    auto& gl = m.gl;
    const int w = m.context->width(), h = m.context->height();

    // Shadow pass: an orthographic sun view of the square around the focus point.
    const Eigen::Vector3f sun = light.sunDirection.normalized();
    const Eigen::Vector3f lightEye = light.shadowFocus - sun * 60.0f;
    const Eigen::Vector3f lightUp = std::abs(sun.y()) > 0.99f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitY();
    const Eigen::Matrix4f lightViewProj =
        ortho(light.shadowExtent, light.shadowExtent, 1.0f, 150.0f) * lookAt(lightEye, light.shadowFocus, lightUp);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    if (m.shadowSize > 0) {
        gl.BindFramebuffer(GL_FRAMEBUFFER, m.shadowFbo);
        gl.Viewport(0, 0, m.shadowSize, m.shadowSize);
        gl.Clear(GL_DEPTH_BUFFER_BIT);
        gl.Disable(GL_CULL_FACE);  // the flag and thin parts cast shadows from both sides
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        gl.PolygonOffset(1.5f, 2.0f);
        gl.UseProgram(m.shadowProgram);
        m.setMat(m.shadowProgram, "uLightViewProj", lightViewProj);
        m.drawItems(items, m.shadowProgram, true);
        gl.Disable(GL_POLYGON_OFFSET_FILL);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    // Main pass.
    if (m.msaa) m.msaa->bind();
    gl.Viewport(0, 0, w, h);
    gl.Disable(GL_FRAMEBUFFER_SRGB);  // the shaders encode (see kMeshFragment)
    gl.ClearColor(light.horizonColor.x(), light.horizonColor.y(), light.horizonColor.z(), 1);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const Eigen::Matrix4f viewProj =
        perspective(camera.fovY, float(w) / float(h), camera.nearPlane, camera.farPlane) *
        lookAt(camera.eye, camera.target, camera.up);

    const GLuint p = m.meshProgram;
    gl.UseProgram(p);
    gl.CullFace(GL_BACK);
    m.setMat(p, "uViewProj", viewProj);
    m.setMat(p, "uLightViewProj", lightViewProj);
    m.setVec(p, "uSunDir", sun);
    m.setLinear(p, "uSunColor", light.sunColor);
    m.setLinear(p, "uSky", light.skyColor);
    m.setVec(p, "uHorizon", light.horizonColor);  // fog mixes after encoding: display value
    m.setLinear(p, "uBounce", light.groundBounce);
    m.setVec(p, "uEye", camera.eye);
    gl.Uniform1f(m.loc(p, "uAmbient"), light.ambient);
    gl.Uniform1f(m.loc(p, "uFogDensity"), 0.004f);
    gl.Uniform1i(m.loc(p, "uShadowSize"), m.shadowSize);
    gl.Uniform1i(m.loc(p, "uTexture"), 0);
    gl.Uniform1i(m.loc(p, "uShadow"), 1);
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_2D, m.shadowTexture);
    m.drawItems(items, p, false);

    // The sky last, at the far plane: the depth test skips every pixel geometry already covers.
    gl.DepthFunc(GL_LEQUAL);
    gl.Disable(GL_CULL_FACE);
    gl.UseProgram(m.skyProgram);
    m.setMat(m.skyProgram, "uInvViewProj", viewProj.inverse());
    m.setVec(m.skyProgram, "uSky", light.skyColor);
    m.setVec(m.skyProgram, "uHorizon", light.horizonColor);
    m.setVec(m.skyProgram, "uBounce", light.groundBounce);
    gl.BindVertexArray(m.skyVao);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.BindVertexArray(0);
    gl.DepthFunc(GL_LESS);
    if (m.msaa) m.msaa->resolve();
}

void Renderer::readPixels(std::vector<std::uint8_t>& rgba) {
    Impl& m = *impl_;
    const int w = m.context->width(), h = m.context->height();
    const std::size_t row = std::size_t(w) * 4;
    rgba.resize(row * h);
    m.gl.Finish();
    m.gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    m.gl.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    // GL's rows run bottom-up; images run top-down.
    std::vector<std::uint8_t> tmp(row);
    for (int y = 0; y < h / 2; ++y) {
        std::uint8_t* a = rgba.data() + row * y;
        std::uint8_t* b = rgba.data() + row * (h - 1 - y);
        std::copy(a, a + row, tmp.data());
        std::copy(b, b + row, a);
        std::copy(tmp.data(), tmp.data() + row, b);
    }
}

void Renderer::showPixels(const std::vector<std::uint8_t>& rgba) {
    impl_->shown.show(impl_->gl, rgba, impl_->context->width(), impl_->context->height());
}

void computeSmoothNormals(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
                          std::vector<float>& normals) {
    normals.assign(positions.size(), 0.0f);
    const std::size_t n = positions.size() / 3;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const std::uint32_t i[3] = {indices[t], indices[t + 1], indices[t + 2]};
        if (i[0] >= n || i[1] >= n || i[2] >= n) continue;
        const Eigen::Vector3f a = Eigen::Map<const Eigen::Vector3f>(&positions[3 * i[0]]);
        const Eigen::Vector3f b = Eigen::Map<const Eigen::Vector3f>(&positions[3 * i[1]]);
        const Eigen::Vector3f c = Eigen::Map<const Eigen::Vector3f>(&positions[3 * i[2]]);
        const Eigen::Vector3f face = (b - a).cross(c - a);  // length = twice the area: area weighting
        for (std::uint32_t v : i) Eigen::Map<Eigen::Vector3f>(&normals[3 * v]) += face;
    }
    for (std::size_t v = 0; v < n; ++v) {
        Eigen::Map<Eigen::Vector3f> nv(&normals[3 * v]);
        const float len = nv.norm();
        if (len > 1e-20f) nv /= len;
        else nv = Eigen::Vector3f::UnitY();
    }
}

}  // namespace engine
