#include "mechanics/integrator.h"

#include "mechanics/implicit_euler.h"
#include "mechanics/rk4.h"

namespace viscera::mechanics {

std::unique_ptr<Integrator> MakeIntegrator(const Model& model, Interactions* interactions) {
  switch (model.params().integrator) {
    case IntegratorKind::kImplicitEuler:
      return std::make_unique<ImplicitEulerIntegrator>(model, interactions);
    case IntegratorKind::kRk4: break;
  }
  return std::make_unique<Rk4Integrator>(model, interactions);
}

}  // namespace viscera::mechanics
