#pragma once
// Bullet's btSoftBody as the study's solver kind bullet_softbody (bullet_kind.cpp).

namespace study {

// Adds the kind to the solver registry (once; later calls do nothing).
void registerBulletSoftBody();

}  // namespace study
