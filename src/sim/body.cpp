#include "sim/body.h"

#include <cmath>

#include "core/format.h"
#include "core/parallel.h"

namespace reel {

Status checkPoints(const StepContext& ctx, const std::string& body, const char* what_kind, const std::vector<Vec3>& x,
                   const std::vector<Vec3>& v, const StepBound& bound) {
  auto bad = [&](std::ptrdiff_t i) {
    const double s = v[i].squaredNorm(), r = x[i].squaredNorm();
    // NaN fails every comparison, so test for the good case.
    return !(s <= kRunawaySpeed * kRunawaySpeed && r <= kRunawayDistance * kRunawayDistance);
  };
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  if (deterministicSum(n, [&](std::ptrdiff_t i) { return bad(i) ? 1.0 : 0.0; }) == 0.0) return {};
  std::ptrdiff_t i = 0;
  while (!bad(i)) ++i;
  auto num = [](double a) { return formatNumber(a, 3); };
  std::string what;
  if (!x[i].allFinite())
    what = "position is not finite";
  else if (!v[i].allFinite())
    what = "velocity is not finite";
  else if (v[i].norm() > kRunawaySpeed)
    what = "speed " + num(v[i].norm()) + " m/s ran away (limit " + num(kRunawaySpeed) + " m/s)";
  else
    what = "position ran away (|x| = " + num(x[i].norm()) + " m)";
  std::string hint = "step h = " + num(ctx.h) + " s";
  if (std::isfinite(bound.h_max))
    hint += ", estimated stable bound " + num(bound.h_max) + " s; try more substeps" +
            (std::string(what_kind) == "node" ? " or implicit_euler" : "");
  else
    hint += "; try more substeps, more damping or softer springs";
  return Error(ErrorKind::Unstable, "unstable at frame " + std::to_string(ctx.frame) + " (t = " + num(ctx.t1) +
                                        " s): body '" + body + "' " + what_kind + " " + std::to_string(i) + " " +
                                        what + " (" + hint + ")");
}

}  // namespace reel
