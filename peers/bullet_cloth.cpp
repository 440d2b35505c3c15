#include "peers/bullet_cloth.h"

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

namespace peer {

struct BulletCloth::Impl {
    btSoftBodyRigidBodyCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    std::unique_ptr<btSoftBody> body;
    ~Impl() {
        if (body) world.removeSoftBody(body.get());
    }
};

BulletCloth::BulletCloth(const cloth::Model& model, const cloth::State& state, const std::vector<cloth::Pin>& pins,
                         int iterations, double linkStiffness)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.world.setGravity(btVector3(0, -9.81f, 0));
    btSoftBodyWorldInfo& info = m.world.getWorldInfo();
    info.m_gravity = btVector3(0, -9.81f, 0);
    info.air_density = 0;
    info.m_sparsesdf.Initialize();
    const int n = model.particleCount();
    std::vector<btVector3> x(n);
    std::vector<btScalar> mass(n);
    for (int i = 0; i < n; ++i) {
        x[i] = btVector3(btScalar(state.x(0, i)), btScalar(state.x(1, i)), btScalar(state.x(2, i)));
        mass[i] = btScalar(model.masses()[i]);
    }
    m.body = std::make_unique<btSoftBody>(&info, n, x.data(), mass.data());
    btSoftBody::Material* mat = m.body->appendMaterial();
    mat->m_kLST = btScalar(linkStiffness);
    for (const cloth::Spring& s : model.springs()) m.body->appendLink(s.i, s.j, mat, false);
    for (const cloth::Pin& p : pins) m.body->setMass(p.particle, 0);  // Bullet's pin: infinite mass
    m.body->m_cfg.piterations = iterations;
    m.body->m_cfg.kDP = 0;  // no extra damping: the same undamped cloth as ours
    m.world.addSoftBody(m.body.get());
}

BulletCloth::~BulletCloth() = default;

void BulletCloth::step(double h) { impl_->world.stepSimulation(btScalar(h), 0); }

void BulletCloth::step(double h, const std::vector<cloth::Pin>& pins, const cloth::Points* external,
                       cloth::State& state) {
    btSoftBody& body = *impl_->body;
    auto vec = [](const auto& v) { return btVector3(btScalar(v[0]), btScalar(v[1]), btScalar(v[2])); };
    for (int i = 0; i < body.m_nodes.size(); ++i) {
        btSoftBody::Node& n = body.m_nodes[i];
        n.m_x = n.m_q = vec(state.x.col(i));
        n.m_v = vec(state.v.col(i));
        if (external && n.m_im > 0) body.addForce(vec(external->col(i)), i);
    }
    for (const cloth::Pin& p : pins) {
        btSoftBody::Node& n = body.m_nodes[int(p.particle)];
        n.m_x = n.m_q = vec(p.x);
        n.m_v = vec(p.v);
    }
    step(h);
    for (int i = 0; i < body.m_nodes.size(); ++i)
        for (int a = 0; a < 3; ++a) state.x(a, i) = body.m_nodes[i].m_x[a], state.v(a, i) = body.m_nodes[i].m_v[a];
}

void BulletCloth::positions(cloth::Points& x) const {
    const auto& nodes = impl_->body->m_nodes;
    x.resize(3, nodes.size());
    for (int i = 0; i < nodes.size(); ++i)
        for (int a = 0; a < 3; ++a) x(a, i) = nodes[i].m_x[a];
}

}  // namespace peer
