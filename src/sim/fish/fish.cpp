#include "sim/fish/fish.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace reel {
namespace {

// The body's shape (thesis §4.1: a streamlined body, greatest girth a little ahead of the
// middle): rings at fractions s of the length from the nose, with half-widths and half-heights
// in lengths.
constexpr std::array<double, 5> kRingAt = {0.12, 0.28, 0.45, 0.62, 0.80};
constexpr std::array<double, 5> kHalfWidth = {0.045, 0.060, 0.055, 0.035, 0.015};
constexpr std::array<double, 5> kHalfHeight = {0.070, 0.095, 0.085, 0.055, 0.025};
constexpr double kTailTip = 0.11;  // the tail fin's half-height, lengths

int ring(int r, int corner) { return 1 + 4 * r + corner; }  // r 0..4, corner 0 UL, 1 UR, 2 LR, 3 LL

}  // namespace

FishTemplate makeFishTemplate(double L, double density) {
  FishTemplate t;
  t.x[0] = Vec3(0, 0, 0);
  const double sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 4; ++c) t.x[ring(r, c)] = L * Vec3(sx[c] * kHalfWidth[r], sy[c] * kHalfHeight[r], -kRingAt[r]);
  t.x[21] = L * Vec3(0, kTailTip, -1.0);
  t.x[22] = L * Vec3(0, -kTailTip, -1.0);

  // Masses: each ring carries the elliptic slice of the body around it (from halfway to the ring
  // before to halfway to the next), a quarter per node; the nose and tail tips a little.
  const double rho = density > 0 ? density : 1000.0;
  for (int r = 0; r < 5; ++r) {
    const double before = r == 0 ? kRingAt[0] : 0.5 * (kRingAt[r] - kRingAt[r - 1]);
    const double after = 0.5 * ((r == 4 ? 1.0 : kRingAt[r + 1]) - kRingAt[r]);
    const double volume = kPi * kHalfWidth[r] * kHalfHeight[r] * (before + after) * L * L * L;
    for (int c = 0; c < 4; ++c) t.mass[static_cast<std::size_t>(ring(r, c))] = rho * volume / 4;
  }
  t.mass[0] = 0.5 * t.mass[1];
  t.mass[21] = t.mass[22] = 0.5 * t.mass[17];
  double total = 0;
  for (int i = 0; i < kFishNodes; ++i) total += t.mass[static_cast<std::size_t>(i)], t.center_of_mass += t.mass[static_cast<std::size_t>(i)] * t.x[static_cast<std::size_t>(i)];
  t.center_of_mass /= total;
  t.total_mass = total;

  // Stiffness: the cross struts keep the body's section and are the stiffest, the muscles the
  // softest (thesis §4.1, footnote to Table 4.1). Muscle force grows with the section (∝ L²) and
  // a spring's stiffness is force over stretch, so it scales as L: the body's own frequencies fall
  // as 1/L, as the largest tail beat of real fish does. The scale lets the body follow its muscles
  // against the water's push to 4 beats a second and more at 0.3–1 m. Damping ≈ 0.2 of critical for a mean node.
  const double mean_mass = total / kFishNodes;
  const double k_muscle = 22400.0 * L, k_other = 1.1 * k_muscle, k_cross = 1.4 * k_muscle;
  auto add = [&](int a, int b, double k) {
    const double rest = (t.x[static_cast<std::size_t>(b)] - t.x[static_cast<std::size_t>(a)]).norm();
    t.springs.add(a, b, k, 0.4 * std::sqrt(k * mean_mass), rest);
  };
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 4; ++c) add(ring(r, c), ring(r, (c + 1) % 4), k_other);
    add(ring(r, 0), ring(r, 2), k_cross);
    add(ring(r, 1), ring(r, 3), k_cross);
  }
  for (int r = 0; r < 4; ++r) {
    // Lengthwise units; rings 2–3, 3–4, 4–5 (r = 1, 2, 3) are the muscle segments.
    for (int c = 0; c < 4; ++c) {
      if (r >= 1) {
        // Muscle order: segment, side (left = corners 0 and 3), upper then lower.
        const int side = (c == 0 || c == 3) ? 0 : 1, lower = (c >= 2) ? 1 : 0;
        t.muscle[static_cast<std::size_t>(4 * (r - 1) + 2 * side + lower)] = static_cast<int>(t.springs.size());
      }
      add(ring(r, c), ring(r + 1, c), r >= 1 ? k_muscle : k_other);
    }
    for (int c = 0; c < 4; ++c) {  // the two diagonals of each side face
      add(ring(r, c), ring(r + 1, (c + 1) % 4), k_other);
      add(ring(r, (c + 1) % 4), ring(r + 1, c), k_other);
    }
  }
  for (int c = 0; c < 4; ++c) add(0, ring(0, c), k_other);
  for (int c = 0; c < 4; ++c) add(ring(4, c), 21, k_other), add(ring(4, c), 22, k_other);
  add(21, 22, k_other);

  // The surface, counter-clockwise seen from outside.
  int k = 0;
  // (Listed as built, then reversed: the rings run clockwise seen from ahead.)
  auto tri = [&](int a, int b, int c) { t.surface[static_cast<std::size_t>(k++)] = {a, c, b}; };
  int nf = 0;
  auto face = [&](int a, int b, int c, int d) { t.faces[static_cast<std::size_t>(nf++)] = {a, b, c, d}; };
  for (int c = 0; c < 4; ++c) {
    tri(0, ring(0, (c + 1) % 4), ring(0, c));
    face(0, ring(0, c), ring(0, (c + 1) % 4), -1);
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const int a = ring(r, c), b = ring(r, (c + 1) % 4), a2 = ring(r + 1, c), b2 = ring(r + 1, (c + 1) % 4);
      // Each quad split along one diagonal for drawing and contacts; the flanks' diagonals
      // mirror each other (upper front to lower back on both).
      if (c == 3) {
        tri(a, b, a2);
        tri(b, b2, a2);
      } else {
        tri(a, b, b2);
        tri(a, b2, a2);
      }
      face(a, a2, b2, b);
    }
  // Around the tail: top and bottom wedges, the two flanks of the fin.
  tri(ring(4, 0), ring(4, 1), 21);
  face(ring(4, 0), 21, ring(4, 1), -1);
  tri(ring(4, 2), ring(4, 3), 22);
  face(ring(4, 2), 22, ring(4, 3), -1);
  tri(ring(4, 3), ring(4, 0), 21);
  tri(ring(4, 3), 21, 22);
  face(ring(4, 3), 22, 21, ring(4, 0));
  tri(ring(4, 1), ring(4, 2), 21);  // the right flank split as the left's mirror
  tri(ring(4, 2), 22, 21);
  face(ring(4, 1), 21, 22, ring(4, 2));
  return t;
}

void motorControl(const MotorCommand& cmd, double forward_speed, double length, double h, FishMotor& m) {
  // The swim-MC (thesis §4.4.1): speed roughly proportional to the tail beat's amplitude and
  // frequency (Webb 1989). A beat at full amplitude moves this fish about 0.7 of its length, and
  // about 0.7 √amplitude at less (measured on this model: 0.36, 0.54, 0.68 lengths a beat at
  // amplitude 0.4, 0.7, 1); an integral term takes the rest of the way to the speed asked for.
  // The feed-forward takes a shorter stride than a beat makes, so a change of speed starts with a
  // strong beat and the integral term trims it: fed the measured stride, a school's fish answered
  // their neighbours too slowly and the school spread.
  constexpr double kStride = 0.7, kFeedStride = 0.4, kMaxBeat = 2.1;  // lengths per beat; beats per second at 1 m
  const double max_frequency = kMaxBeat / std::sqrt(std::max(length, 1e-3));
  if (cmd.speed >= 0) {
    const double target = cmd.speed;
    m.speed_error = std::clamp(m.speed_error + h * (target - forward_speed), -length, length);
    // Amplitude from 0.4 at rest to full at a third of the top speed; frequency then carries
    // the rest (as fish cruise: Bainbridge 1958). (Cruising at two-thirds amplitude, schools of
    // these fish kept less order.)
    m.amplitude = target > 0 ? std::clamp(0.4 + 0.6 * target / (length * max_frequency * kStride / 3), 0.4, 1.0) : 0.0;
    const double feed = target / (kFeedStride * length * std::sqrt(std::max(m.amplitude, 0.4)));
    m.frequency = target > 0 ? std::clamp(feed + 2.0 * m.speed_error / length, 0.0, max_frequency) : 0.0;
  }
  // Faster than asked by a quarter or more, both pectoral fins open as brakes, fully at half
  // again the speed asked (a streamlined body glides far).
  double brake = 0.0;
  if (cmd.speed >= 0) {
    const double excess = forward_speed - cmd.speed;
    brake = (kPi / 3) * std::clamp(4.0 * excess / std::max(cmd.speed, 0.2 * length) - 1.0, 0.0, 1.0);
  } else {
    m.frequency = cmd.frequency;
    m.amplitude = cmd.amplitude;
    m.speed_error = 0.0;
  }
  // Toward the commanded bend and fin pitch at a muscle's pace (about a tenth of a second).
  const double rate = std::min(1.0, h / 0.1);
  m.bend += rate * (std::clamp(cmd.bend, -1.0, 1.0) - m.bend);
  m.pitch += rate * (cmd.pitch - m.pitch);
  m.yaw += rate * (std::clamp(cmd.yaw, -kPi / 3, kPi / 3) - m.yaw);
  m.brake += rate * (brake - m.brake);
  m.phase = std::fmod(m.phase + 2 * kPi * m.frequency * h, 2 * kPi);

  // Contractions: middle and rear segments swim (the rear lags by π/2), front and middle turn.
  m.contraction.fill(0.0);
  for (int seg = 1; seg <= 2; ++seg) {
    const double s = std::sin(m.phase - 0.5 * kPi * (seg - 1));
    for (int lower = 0; lower < 2; ++lower) {
      m.contraction[static_cast<std::size_t>(4 * seg + lower)] += m.amplitude * std::max(0.0, s);
      m.contraction[static_cast<std::size_t>(4 * seg + 2 + lower)] += m.amplitude * std::max(0.0, -s);
    }
  }
  for (int seg = 0; seg <= 1; ++seg) {
    const int side = m.bend > 0 ? 0 : 1;  // left muscles bend the body to the left
    const double amount = std::abs(m.bend);
    for (int lower = 0; lower < 2; ++lower) m.contraction[static_cast<std::size_t>(4 * seg + 2 * side + lower)] += amount;
  }
  for (double& c : m.contraction) c = std::clamp(c, 0.0, 1.0);
}

void trackHeading(FishMotor& m, const Vec3& forward, double h) {
  Vec3 c(m.heading[0], m.heading[1], m.heading[2]);
  c = unitOr(c + std::min(1.0, h / 0.3) * (forward - c), forward);
  m.heading = {c.x(), c.y(), c.z()};
}

double turnByAngle(FishMotor& m, int side, double angle, double amount) {
  if (m.turn_done) return 0.0;
  const Vec3 now = unitOr(Vec3(m.heading[0], 0.0, m.heading[2]), Vec3::UnitZ());
  if (m.turn_from[0] == 0 && m.turn_from[2] == 0) m.turn_from = {now.x(), 0.0, now.z()};
  // The level course's change since the last step, added up: any angle, whole turns included.
  const Vec3 from(m.turn_from[0], 0.0, m.turn_from[2]);
  m.turned += std::atan2(from.cross(now).y(), from.dot(now));
  m.turn_from = {now.x(), 0.0, now.z()};
  const double left = side * angle - m.turned;
  if (side * left <= 0) {
    m.turn_done = 1;
    return 0.0;
  }
  return amount * std::clamp(left / (kPi / 6), -1.0, 1.0);
}

FishFrame fishFrame(const Vec3* x, const Vec3* v) {
  FishFrame f;
  Vec3 c[5];
  Vec3 vel{0, 0, 0}, up{0, 0, 0}, left{0, 0, 0};
  for (int r = 0; r < 5; ++r) {
    c[r] = 0.25 * (x[ring(r, 0)] + x[ring(r, 1)] + x[ring(r, 2)] + x[ring(r, 3)]);
    for (int k = 0; k < 4; ++k) vel += v[ring(r, k)];
    up += (x[ring(r, 0)] + x[ring(r, 1)]) - (x[ring(r, 2)] + x[ring(r, 3)]);
    left += (x[ring(r, 0)] + x[ring(r, 3)]) - (x[ring(r, 1)] + x[ring(r, 2)]);
  }
  f.center = 0.2 * (c[0] + c[1] + c[2] + c[3] + c[4]);
  f.forward = unitOr(x[0] - c[2], Vec3::UnitZ());
  f.up = unitOr(up - up.dot(f.forward) * f.forward, Vec3::UnitY());
  f.left = f.up.cross(f.forward);
  f.mouth = x[0];
  f.velocity = vel / 20.0;
  return f;
}

}  // namespace reel
