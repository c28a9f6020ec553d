// The face's muscles and their activations. Waters 1987 ("A muscle model for animating
// three-dimensional facial expression", SIGGRAPH '87): a linear muscle pulls the nodes in a cone
// around it toward its attachment on the bone, with angular and radial fall-off; a sphincter
// squeezes the nodes inside an ellipse toward its centre. As in Lee, Terzopoulos & Waters 1995,
// they act as forces on the muscle layer's nodes (the fascia), and the skin follows through the
// tissue.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/scene/face.h"
#include "core/types.h"
#include "sim/face/head.h"

namespace reel {

struct FaceMuscle {
  FaceMuscleDesc desc;            // points in the head frame
  std::vector<int> nodes;         // the surface vertices whose fascia nodes it pulls
  std::vector<double> weight;     // their shares of its strength (sum 1)
  double jaw = 0.0;               // the jaw's share at its attachment (a linear muscle's moves with it)
};

// The muscles of reel's head (kFacePairedMuscles, kFaceMidlineMuscles) placed on its surface.
std::vector<FaceMuscleDesc> defaultMuscles(const FaceSurface& s);

// The nearest of `points` to p (the first of equals): its index and distance.
std::pair<std::size_t, double> nearestOf(std::span<const Vec3> points, const Vec3& p);

// A muscle's zone over the fascia nodes at rest (`fascia`: their head-frame positions); BadInput
// (naming its path) when the attachment is not on the skull or the insertion not in the tissue,
// or no node lies in its zone.
Result<FaceMuscle> placeMuscle(const FaceMuscleDesc& d, const FaceSurface& s, const std::vector<Vec3>& fascia,
                               const std::string& file);

// The direction of muscle m's pull on a fascia node at p, with its attachment, centre and plane
// axes in the same frame as p.
Vec3 musclePull(const FaceMuscle& m, const Vec3& p, const Vec3& attachment, const Vec3& center, const Vec3& axis_u,
                const Vec3& axis_v);

// A sphincter's plane axes: u along the head's x (made perpendicular to the normal), v up.
void sphincterAxes(const Vec3& normal, Vec3& u, Vec3& v);

// The controls of a face (its muscles' names, then kFaceControls) and, per activation key, the
// contraction of each; BadInput for a name or preset it does not have.
struct FaceActivations {
  std::vector<std::string> controls;
  std::vector<double> times;               // s (keys)
  std::vector<std::vector<double>> values;  // per key, per control
  std::vector<double> blinks;              // s
  // Speech: the visemes' keys, each control's contraction per key, added to the activations.
  std::vector<double> speech_times;
  std::vector<std::vector<double>> speech;
  // The contractions at time t: linear between keys, held outside, blinks on top.
  void at(double t, std::vector<double>& out) const;
  int index(const std::string& control) const;
};
Result<FaceActivations> makeActivations(const FaceDesc& desc, const std::vector<FaceMuscle>& muscles,
                                        const std::string& file);

// A key fraction s in [0, 1] eased in and out (smoothstep, 3s² − 2s³): a face's keys (its
// activations, visemes and the head's turns) start and stop without a kink.
double easeKey(double s);

// How closed a blink started at 0 is at time t after (0 open, 1 closed): 0.08 s closing, 0.04 s
// closed, 0.13 s opening.
double blinkClosure(double t);

}  // namespace reel
