// Rendering of a scene: context, renderer, meshes, camera.

#include "runtime/scene_view.h"

#include <cmath>
#include <stdexcept>

#include "engine/assets/primitives.h"
#include "engine/scene/config_error.h"
#ifdef FLAGSIM_HAS_BULLET
#include "engine/physics/vehicle_world.h"
#endif
#include "engine/render/renderer.h"
#include "render/frame_aa.h"
#include "runtime/vehicle_system.h"
#ifdef FLAGSIM_HAS_ASSIMP
#include "engine/assets/model_loader.h"
#endif
#ifdef FLAGSIM_HAS_IMGUI
#include "ui/panel.h"
#endif
#ifdef FLAGSIM_HAS_SDL2
#include <SDL.h>
#endif

namespace engine {

namespace {

Eigen::Matrix4f toMatrix(const Eigen::Isometry3d& t) { return t.matrix().cast<float>(); }

Eigen::Vector3f vec(const Vec3d& v) { return Eigen::Vector3f(float(v[0]), float(v[1]), float(v[2])); }

}  // namespace

struct SceneView::Impl {
    const SceneConfig* scene = nullptr;
    const VehicleSystem* vehicle = nullptr;
    const Flag* flag = nullptr;
    std::unique_ptr<GLContext> context;
    std::unique_ptr<Renderer> renderer;
    std::vector<DrawItem> staticItems;
    std::vector<int> bodyMeshes;
    int wheelMesh = -1, poleMesh = -1, flagMesh = -1;
    std::vector<float> flagPositions, flagNormals;
    std::vector<std::uint32_t> flagIndices;
    std::vector<std::uint8_t> pixels;
    FrameAntiAliasing frameAa;  // the post pass (render.aa = post), over the pixels read back
    Camera camera;
    bool cameraStarted = false;
    Eigen::Vector3d chaseHeading = Eigen::Vector3d::UnitZ();  // the eased heading the chase camera follows
    bool windowOpen = true;
    bool readback = false;  // read every frame back, even from a window
#ifdef FLAGSIM_HAS_IMGUI
    std::unique_ptr<Panel> panel;
#endif
    bool overlay = false;   // the panel goes into the recorded frames
    struct Orbit {          // the camera command's orbit about the target
        double yaw = 0, pitch = 0, zoom = 1;
    } orbit, pendingOrbit;
    bool dragging = false, orbitMoved = false;

    void createContext();
    void createPanel(bool interactive);
    bool takeEvent(const void* event);
    Camera orbited() const;
    void drawPanel(const PanelState* state, double frameSeconds);
    void addGroundAndPole();
    void addVehicleMeshes();
    void addFlagMesh();
    void updateCamera();
    std::optional<FrameAntiAliasing::Rect> overlayArea() const;
    std::vector<DrawItem> drawList();
};

// Opens the GL context (a window or offscreen) and the renderer on it.
void SceneView::Impl::createContext() {
    const int w = scene->render.width, h = scene->render.height;
    std::string error;
    context = (scene->subsystems & kWindow) ? createWindowContext(w, h, "flagsim: " + scene->name, &error)
                                            : createOffscreenContext(w, h, &error);
    if (!context) throw ConfigError(scene->file + ": render: " + error);
    try {
        renderer = std::make_unique<Renderer>(*context, scene->render.shadowMapSize, scene->render.aa, scene->render.msaa);
    } catch (const std::runtime_error& e) {
        throw ConfigError(scene->file + ": render: " + e.what());
    }
}

// Adds the textured ground and the pole's mesh (the vehicle's pole, or the scene's fixed one).
void SceneView::Impl::addGroundAndPole() {
    Renderer& r = *renderer;
    const int groundTexture = r.addTexture(makeGroundTexture(512), 512, 512);
    Material groundMat;
    groundMat.color = {1, 1, 1};
    groundMat.texture = groundTexture;
    staticItems.push_back({r.addMesh(makeGround(vehicle ? 600.f : 60.f, 4.f), groundMat), Eigen::Matrix4f::Identity(), false});

    Material poleMat;
    poleMat.color = {0.75f, 0.75f, 0.78f};
    const double poleRadius = vehicle ? scene->vehicle.poleRadius : scene->pole.radius;
    const double poleHeight = vehicle ? scene->vehicle.poleHeight : scene->pole.height;
    poleMesh = r.addMesh(makeCylinder(float(poleRadius), float(poleHeight / 2), 16), poleMat);
}

// Adds the meshes of the ground props, the vehicle's body and its wheels.
void SceneView::Impl::addVehicleMeshes() {
    Renderer& r = *renderer;
#ifdef FLAGSIM_HAS_BULLET
    Material propMat;
    propMat.color = {0.62f, 0.58f, 0.5f};
    for (const GroundProp& prop : vehicle->props()) {
        const MeshData mesh = prop.shape == GroundProp::Shape::Box
                                  ? makeBox(float(prop.halfExtents.x()), float(prop.halfExtents.y()), float(prop.halfExtents.z()))
                                  : makeCylinder(float(prop.halfExtents.x()), float(prop.halfExtents.y()), 24);
        staticItems.push_back({r.addMesh(mesh, propMat), toMatrix(prop.transform)});
    }
#endif
    // The body: the scene's model fitted onto the chassis box, or the box itself.
    const Eigen::Vector3d he = vehicle->chassisHalfExtents();
    const float half[3] = {float(he.x()), float(he.y()), float(he.z())};
#ifdef FLAGSIM_HAS_ASSIMP
    LoadedModel model = loadModel(scene->vehicle.model);
    placeModel(model, half, scene->vehicle.modelTransform);
    for (const MeshData& part : model.parts) {
        Material mat;
        mat.color = {part.color[0], part.color[1], part.color[2]};
        bodyMeshes.push_back(r.addMesh(part, mat));
    }
#else
    Material body;
    body.color = {0.8f, 0.15f, 0.1f};
    bodyMeshes.push_back(r.addMesh(makeBox(half[0], half[1], half[2]), body));
#endif
    Material tyre;
    tyre.color = {0.08f, 0.08f, 0.09f};
    wheelMesh = r.addMesh(makeCylinder(float(vehicle->wheelRadius()), float(vehicle->wheelWidth() / 2), 24), tyre);
}

// Adds the flag's dynamic mesh: the model's triangles, textured across the grid.
void SceneView::Impl::addFlagMesh() {
    Renderer& r = *renderer;
    const cloth::Model& model = flag->model();
    const int nx = model.gridNx(), ny = model.gridNy();
    std::vector<float> uvs;
    for (int row = 0; row < ny; ++row)
        for (int col = 0; col < nx; ++col) uvs.insert(uvs.end(), {float(col) / (nx - 1), float(row) / (ny - 1)});
    for (const cloth::Triangle& t : model.triangles())
        flagIndices.insert(flagIndices.end(), {std::uint32_t(t[0]), std::uint32_t(t[1]), std::uint32_t(t[2])});
    const int flagTexture = r.addTexture(makeFlagTexture(384, 256), 384, 256);
    Material flagMat;
    flagMat.color = {1, 1, 1};
    flagMat.texture = flagTexture;
    flagMat.doubleSided = true;
    flagMesh = r.addDynamicMesh(std::size_t(model.particleCount()), flagIndices, uvs, flagMat);
}

SceneView::SceneView(const SceneConfig& scene, const RunOptions& options, const VehicleSystem* vehicle,
                     const Flag* flag)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.scene = &scene;
    m.vehicle = vehicle;
    m.flag = flag;
    m.readback = options.readback || (scene.subsystems & kRecording);  // the recording takes every frame
    m.createContext();
    m.overlay = options.overlay;
    if ((scene.subsystems & kWindow) || options.overlay) m.createPanel(scene.subsystems & kWindow);
    m.addGroundAndPole();
    if (vehicle) m.addVehicleMeshes();
    if (flag) m.addFlagMesh();
}

SceneView::~SceneView() = default;
int SceneView::contextsCreated() { return GLContext::contextsCreated(); }

bool SceneView::hasWindow() const { return impl_->context->isWindow(); }
bool SceneView::windowClosed() const { return !impl_->windowOpen; }

// The panel, or an error naming what is missing (a build without Dear ImGui has none).
void SceneView::Impl::createPanel(bool interactive) {
#ifdef FLAGSIM_HAS_IMGUI
    try {
        panel = std::make_unique<Panel>(*context, interactive);
    } catch (const std::runtime_error& e) {
        throw ConfigError(scene->file + ": render: " + e.what());
    }
#else
    (void)interactive;
    if (overlay) throw ConfigError("--overlay: this build has no panel (Dear ImGui was not found at configure time)");
#endif
}

// The panel first; outside it the left button drags the camera's orbit and the wheel zooms.
bool SceneView::Impl::takeEvent(const void* event) {
#ifdef FLAGSIM_HAS_IMGUI
    if (panel && panel->handleEvent(event)) return true;
#endif
#ifdef FLAGSIM_HAS_SDL2
    const SDL_Event& e = *static_cast<const SDL_Event*>(event);
    if (e.type == SDL_MOUSEBUTTONDOWN && e.button.button == SDL_BUTTON_LEFT) dragging = true;
    if (e.type == SDL_MOUSEBUTTONUP && e.button.button == SDL_BUTTON_LEFT) dragging = false;
    if (e.type == SDL_MOUSEMOTION && dragging) {
        pendingOrbit.yaw = std::remainder(pendingOrbit.yaw - 0.3 * e.motion.xrel, 360.0);
        pendingOrbit.pitch = std::clamp(pendingOrbit.pitch + 0.3 * e.motion.yrel, -80.0, 80.0);
        orbitMoved = true;
    }
    if (e.type == SDL_MOUSEWHEEL) {
        pendingOrbit.zoom = std::clamp(pendingOrbit.zoom * std::pow(0.9, e.wheel.y), 0.2, 5.0);
        orbitMoved = true;
    }
    return e.type == SDL_MOUSEBUTTONDOWN || e.type == SDL_MOUSEBUTTONUP || e.type == SDL_MOUSEMOTION ||
           e.type == SDL_MOUSEWHEEL;
#else
    (void)event;
    return false;
#endif
}

Actions SceneView::pollActions() {
    Actions a;
    Impl& m = *impl_;
    m.windowOpen = m.context->pollEvents(a, [&m](const void* e) { return m.takeEvent(e); }) && m.windowOpen;
    return a;
}

std::string SceneView::antiAliasing() const {
    const AntiAliasing aa = impl_->renderer->antiAliasing();
    std::string text = aa == AntiAliasing::Msaa ? "msaa " + std::to_string(impl_->scene->render.msaa) : toString(aa);
    if (impl_->scene->render.aa == AntiAliasing::Auto) text += " (auto on " + impl_->renderer->glRenderer() + ")";
    return text;
}

bool SceneView::hasPanel() const {
#ifdef FLAGSIM_HAS_IMGUI
    return impl_->panel != nullptr;
#else
    return false;
#endif
}

PanelRequests SceneView::takeRequests() {
    Impl& m = *impl_;
    PanelRequests r;
#ifdef FLAGSIM_HAS_IMGUI
    if (m.panel) r = m.panel->takeRequests();
#endif
    if (m.orbitMoved) {
        char value[96];
        std::snprintf(value, sizeof value, "%.3f,%.3f,%.4f", m.pendingOrbit.yaw, m.pendingOrbit.pitch, m.pendingOrbit.zoom);
        r.commands.push_back({"camera", value});
        m.orbitMoved = false;
    }
    return r;
}

void SceneView::setOrbit(double yawDeg, double pitchDeg, double zoom) {
    impl_->orbit = {yawDeg, pitchDeg, zoom};
    impl_->pendingOrbit = impl_->orbit;
}

std::optional<std::array<float, 4>> SceneView::widgetRect(const std::string& label) const {
#ifdef FLAGSIM_HAS_IMGUI
    if (impl_->panel) return impl_->panel->widgetRect(label);
#endif
    (void)label;
    return std::nullopt;
}

std::vector<std::string> SceneView::widgetLabels() const {
#ifdef FLAGSIM_HAS_IMGUI
    if (impl_->panel) return impl_->panel->widgetLabels();
#endif
    return {};
}

// The eye turned about the target by the orbit: yaw about the vertical, pitch up, the distance
// scaled by zoom.
Camera SceneView::Impl::orbited() const {
    Camera c = camera;
    if (orbit.yaw == 0 && orbit.pitch == 0 && orbit.zoom == 1) return c;
    const Eigen::Vector3d offset = (c.eye - c.target).cast<double>();
    const double r = offset.norm(), flat = std::hypot(offset.x(), offset.z());
    const double azimuth = std::atan2(offset.z(), offset.x()) + orbit.yaw * M_PI / 180;
    const double elevation = std::clamp(std::atan2(offset.y(), flat) + orbit.pitch * M_PI / 180, -0.1, 1.45);
    const double d = r * orbit.zoom;
    c.eye = c.target + Eigen::Vector3d(d * std::cos(elevation) * std::cos(azimuth), d * std::sin(elevation),
                                       d * std::cos(elevation) * std::sin(azimuth)).cast<float>();
    return c;
}

void SceneView::Impl::updateCamera() {
    const SceneConfig::Camera& c = scene->camera;
    camera.fovY = float(c.fov);
    if (c.mode == "fixed" || !vehicle) {
        camera.eye = vec(c.eye);
        camera.target = vec(c.target);
        return;
    }
    // Chase: behind the vehicle along its heading (flattened). The heading is eased each frame,
    // the position is not, so the vehicle and its flag keep their place in the frame at any speed.
    const Eigen::Isometry3d t = vehicle->chassisTransform();
    Eigen::Vector3d forward = vehicle->forward();
    forward.y() = 0;
    if (forward.norm() < 1e-6) forward = Eigen::Vector3d::UnitZ();
    forward.normalize();
    if (!cameraStarted) chaseHeading = forward;
    cameraStarted = true;
    chaseHeading = (chaseHeading + c.smoothing * (forward - chaseHeading)).normalized();
    const Eigen::Vector3d left = Eigen::Vector3d::UnitY().cross(chaseHeading);
    camera.target = (t.translation() + Eigen::Vector3d(0, c.targetHeight, 0)).cast<float>();
    camera.eye = (t.translation() - c.distance * chaseHeading + c.side * left + Eigen::Vector3d(0, c.height, 0))
                     .cast<float>();
}

std::vector<DrawItem> SceneView::Impl::drawList() {
    std::vector<DrawItem> items = staticItems;
    Eigen::Isometry3d carrier = Eigen::Isometry3d::Identity();
    Eigen::Vector3d poleBase(scene->pole.base[0], scene->pole.base[1], scene->pole.base[2]);
    double poleHeight = scene->pole.height;
    if (vehicle) {
        carrier = vehicle->chassisTransform();
        Eigen::Isometry3d body = carrier;
        body.translate(vehicle->bodyOffset());
        for (int mesh : bodyMeshes) items.push_back({mesh, toMatrix(body)});
        for (int i = 0; i < vehicle->wheelCount(); ++i) {
            Eigen::Isometry3d wheel = vehicle->wheelTransform(i);
            wheel.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));  // cylinder axis y -> axle x
            items.push_back({wheelMesh, toMatrix(wheel)});
        }
        const PoleMount mount = vehicle->poleMount();
        poleBase = mount.base;
        poleHeight = mount.height;
    }
    Eigen::Isometry3d pole = carrier;
    pole.translate(poleBase + Eigen::Vector3d(0, poleHeight / 2, 0));
    items.push_back({poleMesh, toMatrix(pole)});
    if (flag) {
        const cloth::Points& x = flag->state().x;
        flagPositions.resize(std::size_t(x.size()));
        for (Eigen::Index i = 0; i < x.size(); ++i) flagPositions[std::size_t(i)] = float(x.data()[i]);
        computeSmoothNormals(flagPositions, flagIndices, flagNormals);
        renderer->updateDynamicMesh(flagMesh, flagPositions, flagNormals);
        items.push_back({flagMesh, Eigen::Matrix4f::Identity()});
    }
    return items;
}

void SceneView::Impl::drawPanel(const PanelState* state, double frameSeconds) {
#ifdef FLAGSIM_HAS_IMGUI
    if (panel && state) panel->draw(*state, context->width(), context->height(), frameSeconds);
#else
    (void)state, (void)frameSeconds;
#endif
}

// The panel's rectangle in the recorded frames (--overlay), which the post pass leaves alone.
std::optional<FrameAntiAliasing::Rect> SceneView::Impl::overlayArea() const {
#ifdef FLAGSIM_HAS_IMGUI
    if (!overlay || !panel) return std::nullopt;
    const auto& a = panel->area();
    return FrameAntiAliasing::Rect{int(std::floor(a[0])), int(std::floor(a[1])), int(std::ceil(a[2])), int(std::ceil(a[3]))};
#else
    return std::nullopt;
#endif
}

void SceneView::renderFrame(Profiler& profiler, const PanelState* panel, double frameSeconds) {
    Impl& m = *impl_;
    {
        Profiler::Scope scope(profiler, Phase::Render);
        m.context->makeCurrent();
        m.updateCamera();
        Lighting light;
        light.shadowFocus = m.camera.target;
        light.shadowExtent = 18;
        m.renderer->render(m.orbited(), light, m.drawList());
    }
    const bool post = m.renderer->antiAliasing() == AntiAliasing::Post;
    if (m.overlay) {  // the panel into the recorded frames
        Profiler::Scope scope(profiler, Phase::Overlay);
        m.drawPanel(panel, frameSeconds);
    }
    {
        Profiler::Scope scope(profiler, Phase::Readback);
        // A live window without recording has no use for the pixels, unless the post pass
        // needs them: skip the readback.
        if (m.readback || !m.context->isWindow() || post) m.renderer->readPixels(m.pixels);
    }
    if (post) {  // the frame read back; a window shows the result
        Profiler::Scope scope(profiler, Phase::AntiAlias);
        const std::optional<FrameAntiAliasing::Rect> panel = m.overlayArea();
        m.frameAa.apply(m.pixels, m.scene->render.width, m.scene->render.height, panel ? &*panel : nullptr);
        if (m.context->isWindow()) m.renderer->showPixels(m.pixels);
    }
    if (!m.overlay && m.context->isWindow() && profiler.enabled(Phase::Panel)) {  // the panel on screen only
        Profiler::Scope scope(profiler, Phase::Panel);
        m.drawPanel(panel, frameSeconds);
    }
    Profiler::Scope scope(profiler, Phase::Readback);
    m.context->present();
}

const std::vector<std::uint8_t>& SceneView::pixels() const { return impl_->pixels; }

}  // namespace engine
