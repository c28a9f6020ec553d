// The `face` kind: a muscle-driven face (Terzopoulos & Waters 1990, "Physically-based facial
// modelling, analysis, and animation"; Lee, Terzopoulos & Waters 1995, "Realistic modeling for
// facial animation"). A layered mass-spring tissue (epidermis, dermal–fatty layer, muscle layer)
// over a skull, moved by Waters' linear and sphincter muscles. docs/face.md lists every key.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/scene/body.h"
#include "core/types.h"

namespace reel {

// One tissue layer: its thickness (m) and Young's modulus (Pa); springs take E·V/l² of the
// volume V they stand for.
struct FaceLayerDesc {
  double thickness = 0.0;  // m
  double modulus = 0.0;    // Pa
};

// A muscle of the scene (points in the head's own frame: origin at the head's centre, +y up,
// +z out of the face, +x the head's left; metres).
struct FaceMuscleDesc {
  std::string name;
  bool sphincter = false;
  // Linear (Waters 1987): from the attachment on the skull to the insertion in the tissue; nodes
  // within `angle_deg` of that line and `falloff_end` muscle lengths of the attachment are pulled
  // toward the attachment, fully up to `falloff_start` lengths.
  Vec3 attachment{0, 0, 0}, insertion{0, 0, 0};
  double angle_deg = 30.0;
  double falloff_start = 0.7, falloff_end = 1.15;  // muscle lengths
  // Sphincter: an ellipse around `center` in the plane facing `normal`, semi-axes `radii` (along
  // the head's x and the plane's up); nodes inside are squeezed toward its centre.
  Vec3 center{0, 0, 0}, normal{0, 0, 1};
  std::array<double, 2> radii{0.03, 0.02};  // m
  double strength = 0.5;  // N, the muscle's pull at full contraction, shared by the nodes it moves
  // How much its belly thickens as it contracts, as the push it gives the tissue off the skull at
  // each node, a fraction (0 to 2) of its pull there (0: none; a sphincter's ring pushes the
  // tissue it squeezes forward along its normal, as puckered lips).
  double bulge = 0.0;
  std::string path;       // JSON path (messages)
};

// Activations at one time: presets with their amounts (and side), and single controls.
struct FaceActivationKey {
  double time = 0.0;  // s
  std::vector<std::pair<std::string, double>> presets;  // name → amount 0..1
  std::string side = "both";                             // presets: "both", "left", "right"
  std::vector<std::pair<std::string, double>> muscles;  // control name → contraction 0..1
  std::string path;
};

// The head's pose at one time (eased between keys).
struct FacePoseKey {
  double time = 0.0;
  Vec3 rotation_deg{0, 0, 0};
};

// Where the eyes look at one time (world point; linear between keys).
struct FaceGazeKey {
  double time = 0.0;
  Vec3 target{0, 0, 1};
};

// How the face is drawn from a time on: "skin" or "layers" (cut away: the lattice over the left
// half, the skull, eyes and muscles on the right).
struct FaceDrawKey {
  double time = 0.0;
  bool layers = false;
  double fade = 0.0;  // s: the mode before fades out over this one for so long after `time`
};

// reel's head's looks: sex 0 (female) .. 1 (male): brow ridge, jaw, chin, nose, lips; age (years,
// 18..90): the folds beside the nose and under the eyes, the skin, greying hair; build 0 (lean) ..
// 1 (heavy): cheeks, jaw, neck.
struct FaceLook {
  double sex = 0.5, age = 35.0, build = 0.5;
  bool operator==(const FaceLook&) const = default;
};

// A mouth shape of speech (a viseme) at one time: the lips and jaw reach it at `time` and blend
// linearly to the next key; "rest" is none.
struct FaceVisemeKey {
  double time = 0.0;  // s
  std::string viseme;
  double amount = 1.0;
  std::string path;
};

struct FaceDesc final : BodyParams {
  // The surface: reel's own head (no `mesh`), or a user's closed mesh with its `skull` mesh or an
  // `inset` distance (m) to the bone.
  std::shared_ptr<const TriMesh> mesh, skull;
  std::string mesh_file, skull_file;
  double inset = 0.0;            // m; 0 with a user mesh: the skull mesh is required
  double height = 0.24;          // m, chin to crown of reel's head
  std::array<int, 2> resolution{64, 40};  // reel's head: columns around, rows from crown to neck
  Vec3 position{0, 0, 0};        // m, the head's centre
  Vec3 rotation_deg{0, 0, 0};
  std::vector<FacePoseKey> keys;  // the head's rotation over time (replaces rotation_deg)
  // Tissue (defaults: effective moduli; see docs/face.md).
  FaceLayerDesc epidermis{0.001, 4.0e5};  // a membrane on the surface
  FaceLayerDesc dermis{0.004, 1.5e4};     // dermal–fatty layer
  FaceLayerDesc muscle{0.005, 3.0e3};     // muscle layer, down to the skull
  double biphasic_strain = 0.15;   // past this strain the skin's springs stiffen
  double biphasic_ratio = 5.0;     // by this factor
  double volume_modulus = 2.5e5;   // Pa, resistance of each tissue element to a change of volume
  double density = 1000.0;         // kg/m³
  double damping = 8.0;            // 1/s, each node's drag over its mass
  double spring_damping = 0.002;   // s, a spring's damping over its stiffness
  double gravity_scale = 1.0;
  // m, reel's head: tissue behind the temples and farther than this from every muscle's zone and
  // from the jaw is held to the skull (the scalp over the crown and the back of the head, the back
  // of the neck); 0 holds only the neck's cut end.
  double held_beyond = 0.03;
  bool default_muscles = true;     // reel's head: its muscles (off: only `muscles`)
  std::vector<FaceMuscleDesc> muscles;
  std::vector<FaceActivationKey> activations;
  std::vector<double> blinks;      // s, times at which a blink starts (0.25 s each)
  std::vector<FaceVisemeKey> visemes;  // speech: mouth shapes over time, on top of the activations
  FaceLook look;                   // reel's head
  bool shoulders = true;           // reel's head: draw its shoulders in a sweater
  std::vector<FaceGazeKey> gaze;   // none: the eyes look straight ahead
  std::vector<FaceDrawKey> draw;   // none: skin
  Vec3 iris_color{0.12, 0.22, 0.35};  // linear rgb

  // Three nodes per surface vertex (epidermis, fascia, bone), about twenty-three springs (with the
  // skin's flexion springs).
  std::pair<long long, long long> nodesAndSprings() const override {
    const long long v = mesh ? static_cast<long long>(mesh->vertexCount())
                             : static_cast<long long>(resolution[0] + 1) * (resolution[1] + 3) + 2 + resolution[0] / 2;  // the neck's 4 rings too
    return {3 * v, 23 * v};
  }
};

// The controls activations may name besides muscles: the jaw's opening and the eyelids.
inline constexpr std::array<const char*, 3> kFaceControls = {"jaw_open", "blink", "eyelid_raise"};
// reel's head's muscles: these in pairs (`_left`, `_right`; left is +x) ...
inline constexpr std::array<const char*, 9> kFacePairedMuscles = {
    "zygomatic_major", "zygomatic_minor", "levator_labii", "depressor_anguli_oris",
    "frontalis_inner", "frontalis_outer", "corrugator", "orbicularis_oculi", "risorius"};
// ... and these on the midline.
inline constexpr std::array<const char*, 4> kFaceMidlineMuscles = {"orbicularis_oris", "mentalis", "procerus", "incisivii"};

// An expression preset: controls (paired muscles by their name without side) and their amounts
// at full expression. Ekman's six universal expressions, by the action units FACS gives for them
// (Ekman & Friesen 1978; Ekman, Friesen & Hager 2002), each unit by the muscle that makes it:
// AU1 frontalis inner, AU2 frontalis outer, AU4 corrugator, AU5 eyelid raise, AU6 and AU7
// orbicularis oculi, AU9 and AU10 levator labii, AU12 zygomatic major, AU15 depressor anguli oris,
// AU17 mentalis, AU18 incisivii, AU20 risorius, AU23 and AU24 orbicularis oris, AU26 jaw open. And a blink.
struct FacePreset {
  const char* name;
  std::array<std::pair<const char*, double>, 7> controls;  // unused slots: nullptr
};
inline constexpr std::array<FacePreset, 7> kFacePresets = {{
    // AU6 + AU12 (+ AU13, AU20, AU25/26): the lips a little apart showing the upper teeth.
    {"happiness",
     {{{"zygomatic_major", 1.0}, {"orbicularis_oculi", 1.0}, {"jaw_open", 0.15}, {"risorius", 0.3}, {"zygomatic_minor", 0.1}}}},
    // AU1 + AU4 + AU15 (+ AU17)
    {"sadness", {{{"frontalis_inner", 1.0}, {"corrugator", 0.35}, {"depressor_anguli_oris", 1.0}, {"mentalis", 0.2}, {"orbicularis_oculi", 0.15}}}},
    // AU1 + AU2 + AU5 + AU26
    {"surprise", {{{"frontalis_inner", 1.0}, {"frontalis_outer", 1.0}, {"jaw_open", 0.8}, {"eyelid_raise", 1.0}}}},
    // AU4 + AU5 + AU7 + AU23 (+ AU17)
    {"anger", {{{"corrugator", 1.0}, {"procerus", 1.0}, {"eyelid_raise", 0.8}, {"orbicularis_oculi", 0.5}, {"orbicularis_oris", 1.0}, {"mentalis", 0.5}, {"levator_labii", 0.2}}}},
    // AU9 + AU10 + AU15 (+ AU17)
    {"disgust", {{{"levator_labii", 1.0}, {"procerus", 0.6}, {"corrugator", 0.45}, {"depressor_anguli_oris", 0.5}, {"orbicularis_oculi", 0.45}, {"mentalis", 0.5}}}},
    // AU1 + AU2 + AU4 + AU5 + AU20 + AU26
    {"fear", {{{"frontalis_inner", 1.0}, {"frontalis_outer", 0.6}, {"corrugator", 0.6}, {"eyelid_raise", 1.0}, {"risorius", 1.0}, {"jaw_open", 0.35}}}},
    {"blink", {{{"blink", 1.0}}}},
}};

// Visemes: the mouth's shapes of speech (the lips and the jaw), after the viseme classes of
// MPEG-4 facial animation (ISO/IEC 14496-2, 1999): "aa" (father), "ee" (see), "oo" (you, w),
// "oh" (go), "mbp" (lips closed and pressed), "fv" (lower lip to the upper teeth), "th" (the,
// l, n: tongue-tip sounds, jaw a little open); "rest" is none.
inline constexpr std::array<FacePreset, 7> kFaceVisemes = {{
    {"aa", {{{"jaw_open", 0.65}, {"zygomatic_minor", 0.15}}}},
    {"ee", {{{"risorius", 0.8}, {"zygomatic_major", 0.3}, {"jaw_open", 0.18}}}},
    {"oo", {{{"orbicularis_oris", 1.0}, {"jaw_open", 0.06}, {"incisivii", 1.0}}}},
    {"oh", {{{"orbicularis_oris", 0.65}, {"jaw_open", 0.45}, {"incisivii", 0.6}}}},
    {"mbp", {{{"mentalis", 0.6}, {"orbicularis_oris", 0.35}}}},
    {"fv", {{{"mentalis", 0.8}, {"levator_labii", 0.3}, {"jaw_open", 0.06}}}},
    {"th", {{{"jaw_open", 0.3}, {"risorius", 0.2}}}},
}};

}  // namespace reel
