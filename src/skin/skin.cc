#include "skin/skin.h"

#include <cmath>

#include "common/check.h"
#include "skin/convolution_skin.h"
#include "skin/hybrid_skin.h"
#include "skin/implicit_skin.h"
#include "skin/parametric_skin.h"

namespace viscera::skin {

void ValidateOptions(const SkinOptions& options) {
  ThrowUnless(options.radius > 0.0 && std::isfinite(options.radius),
              "skin radius must be finite and > 0, got ", options.radius);
}

void CheckSnapshot(const Points& q, int bound_rows) {
  ThrowUnless(bound_rows > 0, "skin used before Bind");
  ThrowUnless(q.rows() == bound_rows, "skin bound to ", bound_rows, " control points, got ",
              q.rows());
  ThrowUnless(q.allFinite(), "skeleton snapshot has non-finite coordinates");
}

bool IsSkinName(const std::string& name) {
  for (const char* known : kSkinNames) {
    if (name == known) return true;
  }
  return false;
}

std::unique_ptr<Skin> MakeSkin(const std::string& name, const SkinOptions& options) {
  ValidateOptions(options);
  if (name == "parametric")
    return std::make_unique<ParametricSkin>(options.radius, options.parametric);
  if (name == "convolution") {
    return std::make_unique<ConvolutionSkin>(options.radius, options.convolution);
  }
  if (name == "implicit") return std::make_unique<ImplicitSkin>(options.radius, options.implicit);
  if (name == "hybrid") {
    return std::make_unique<HybridSkin>(options.radius, options.parametric, options.convolution,
                                        options.hybrid);
  }
  Fail("unknown skin '", name, "' (expected ", kSkinNameList, ")");
}

}  // namespace viscera::skin
