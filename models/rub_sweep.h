// The rub model in a time-marching speed sweep (level L3, Kumar 2010 §3.5): what the sweep
// observes at each contact, the impulse that starts the rub, the speed schedule, and the reading
// of whirl, whip and the jumps between them off the sweep's result.
//
// The generic sweep (solvers/sweep.h) knows no model; this file is the rub side of it:
//   channel k (one per contact)  signal d_k = u_rk − u_sk (complex, m): its dominant negative
//                                frequency is the backward precession (BP) at contact k;
//                                active while the contact touches (N_k > 0);
//                                measures slip_velocity V_k [m/s] and normal_force N_k [N].
// The slip velocity is averaged over the samples where the contact touches: the surface velocity
// of the rotor over the stator while they rub (V = ωR + tᵀḋ, models/contact.h).
#pragma once

#include <string>
#include <vector>

#include "models/rub_model.h"
#include "solvers/sweep.h"

namespace rubcont {

// Measure indices of RubSweepObservables.
constexpr int kSlipVelocityMeasure = 0;
constexpr int kNormalForceMeasure = 1;

class RubSweepObservables : public SweepObservables {
 public:
  // The system must outlive the observables (its current ω is used for V).
  explicit RubSweepObservables(RubFixedFrame& system);
  int Channels() const override;
  int Measures() const override { return 2; }
  std::string ChannelName(int channel) const override;   // the contact's name ("left", "right")
  std::string MeasureName(int measure) const override;   // "slip_velocity", "normal_force"
  void Observe(double t, ConstVectorRef x, SweepObservation& out) override;

 private:
  RubFixedFrame& system_;
};

// The state increment of an impulse J [N·s] (≥ 0, finite) applied at t = 0 to the rotor at its
// imbalance (mass-centre) plane along +x: Δv = M⁻¹ b J with b = the structure's imbalance
// weights (two-point rotor: ((1−a), a, 0, 0)), Δq = 0. For the rigid two-point rotor this is a
// pure translation at J/m_r (M_r (1, 1)ᵀ = m_r ((1−a), a)ᵀ): both contact planes move together
// (Mode 1 excitation, as the thesis's impulse; its §4.2 could not start Mode 2 either way).
Vector RubImpulseIncrement(const RubStructure& structure, double impulse);

// Running speeds from `from_rpm` towards `to_rpm` in steps of `step_rpm` (> 0): from, from ± step,
// …, up to and including `to_rpm` when it lies on the grid (within 1e-9 steps), otherwise the
// last value before it. Throws std::invalid_argument for non-finite or non-positive inputs.
std::vector<double> SpeedSchedule(double from_rpm, double to_rpm, double step_rpm);

constexpr double RpmToRadPerSecond(double rpm) { return rpm * 0.10471975511965977; }  // 2π/60
constexpr double RadPerSecondToRpm(double omega) { return omega / 0.10471975511965977; }

// What each contact does at one speed of the sweep. With rolling precession f_roll,k = RCI_k·ω/2π
// (backward precession at which contact k rolls without slipping, models/contact.h):
enum class RubRegime {
  kUnknown,    // the integration failed at this speed
  kNoContact,  // the contact touched for less than min_contact_fraction of the analysed time
  kWhirl,      // |BP − f_roll,k| ≤ whirl_tolerance·f_roll,k: the contact rolls
  kWhip,       // otherwise: the contact slips (BP locked elsewhere, usually below f_roll,k)
};
const char* ToString(RubRegime regime);

struct RubRegimeOptions {
  // Relative distance of the precession from rolling within which a contact whirls (for a
  // circular orbit, normalized slip |V|/(ωR_k)). In [0, 1). The tanh friction law rolls with a
  // micro-slip V ≈ ε·atanh(μ_req/μ) (≈ 2.6ε at μ_req = 0.99μ): far below 2 % of ωR at the
  // thesis's speeds for ε = 1e-3 m/s.
  double whirl_tolerance = 0.02;
  // A jump within one regime: between successive speeds the precession moves by more than this
  // from both trends, whip-like (BP constant) and whirl-like (BP ∝ ω). > 0. The thesis's whip
  // frequency wanders by < 2 Hz between speeds (82.6 → 83 → 84.66 Hz, case B(a)); whirl-like
  // precession at unequal RCIs (both contacts slipping) follows BP ∝ ω without counting as jumps.
  double frequency_jump_hz = 3.0;
  // Below this share of the analysed time in contact, the contact counts as lost. In [0, 1].
  double min_contact_fraction = 0.01;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const RubRegimeOptions& options);

enum class RubJumpKind {
  kWhirlToWhip,
  kWhipToWhirl,
  kContactLost,      // whirl or whip → no contact
  kContactRegained,  // no contact → whirl or whip
  kFrequencyJump,    // same regime, precession off both trends (e.g. whip at another mode)
};
const char* ToString(RubJumpKind kind);

// A change between two successive classified speeds of the schedule (failed speeds skipped).
struct RubSweepJump {
  int contact = 0;                // index into RubStructure::contacts
  RubJumpKind kind = RubJumpKind::kWhirlToWhip;
  double speed_from_rpm = 0.0;    // the last speed before the change
  double speed_to_rpm = 0.0;      // the first speed after it
  double precession_from_hz = 0.0;  // BP at those speeds (NaN where there is no contact)
  double precession_to_hz = 0.0;
  // Both speeds settled (SweepPointStatus::kSettled). When one ran to its dwell instead, the
  // response there was still changing: the jump may belong to a transient (a dwell too short for
  // the speed step's kick to die out), and the speed it is read at may be off by more than a step.
  bool settled = true;
};

struct RubSweepRegimes {
  std::vector<std::vector<RubRegime>> regime;       // [contact][point]
  std::vector<std::vector<double>> precession_hz;   // [contact][point]: BP > 0 backward; NaN: none
  std::vector<RubSweepJump> jumps;                  // in schedule order, then by contact
};

// Reads regimes and jumps off a sweep of the rub model (parameter ω in rad/s).
RubSweepRegimes ClassifySweep(const RubStructure& structure, const std::vector<SweepPoint>& points,
                              const RubRegimeOptions& options = {});

}  // namespace rubcont
