// The rub model in a time-marching speed sweep (level L3, Kumar 2010 §3.5): what the sweep
// observes at each contact, the impulse that starts the rub, the speed schedule, and the reading
// of whirl, whip and the jumps between them off the sweep's result.
//
// The generic sweep (sweeps/sweep.h) knows no model; this file is the rub side of it:
//   channel k (one per contact)  signal d_k = u_rk − u_sk (complex, m): its dominant negative
//                                frequency is the backward precession (BP) at contact k;
//                                active while the contact touches (N_k > 0);
//                                measures slip_velocity V_k [m/s] and normal_force N_k [N].
// The slip velocity is averaged over the samples where the contact touches: the surface velocity
// of the rotor over the stator while they rub (V = ωR + tᵀḋ, models/contact.h).
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "models/rub_model.h"
#include "models/units.h"
#include "solvers/constants.h"
#include "sweeps/attractor.h"
#include "sweeps/ensemble.h"
#include "sweeps/sweep.h"

namespace rubcont {

// Measure indices of RubSweepObservables.
constexpr int kSlipVelocityMeasure = 0;
constexpr int kNormalForceMeasure = 1;
constexpr int kPenetrationMeasure = 2;

class RubSweepObservables : public SweepObservables {
 public:
  // The system must outlive the observables (its current ω is used for V).
  explicit RubSweepObservables(RubFixedFrame& system);
  int Channels() const override;
  int Measures() const override { return 3; }
  std::string ChannelName(int channel) const override;   // the contact's name ("left", "right")
  // "slip_velocity" [m/s], "normal_force" [N], "penetration" δ [m]
  std::string MeasureName(int measure) const override;
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

// The time-marching model at one running speed, options.parameters[0] (its only entry), from
// rest plus an impulse [N·s] (RubImpulseIncrement): one speed of a sweep (SweepStepper, settled by
// options' windows within options.dwell). For a start on the attractor a transient settles on
// (shooting/rub_tori.h: the torus of a two-frequency whip). Throws std::invalid_argument when
// options.parameters does not hold exactly one speed, and as RubImpulseIncrement and SweepStepper.
struct RubSettledSpeed {
  Vector state;      // fixed frame, where the run ended
  SweepPoint point;  // what the sweep read there (status, each contact's spectrum)
  // The backward precession of the first contact [Hz]: minus its spectrum's peak (on the default
  // peak_side, negative frequencies); NaN when the run failed before a spectrum.
  double precession_hz = 0.0;
  bool settled = false;  // point.status == kSettled
};
RubSettledSpeed SettleAtSpeed(const RubStructure& structure, const SweepOptions& options,
                              double impulse);

// SettleAtSpeed's options for a modulated whip or a torus at `omega` [rad/s]: `dwell` s from rest
// (the sweeps' 0.75 s is too short for them), 0.5 s windows over 1 s of analysis, CVODES BDF of
// order ≤ 2 at 1e-6 (A-stable: the nearly undamped contact modes do not limit the step; see
// apps/stage_options.cpp).
SweepOptions LongSettleOptions(double omega, double dwell = 8.0);

// Running speeds from `from_rpm` towards `to_rpm` in steps of `step_rpm` (> 0): from, from ± step,
// …, up to and including `to_rpm` when it lies on the grid (within 1e-9 steps), otherwise the
// last value before it. Throws std::invalid_argument for non-finite or non-positive inputs.
std::vector<double> SpeedSchedule(double from_rpm, double to_rpm, double step_rpm);
// The number of speeds SpeedSchedule gives, without making them: a double, since a schedule a
// plan check refuses (studies/work_plan.h) may count more speeds than any integer type holds.
// Throws as SpeedSchedule.
double SpeedCount(double from_rpm, double to_rpm, double step_rpm);

// What each contact does at one speed of the sweep. Rolling is decided by the slip the sweep
// measures, the frequency is a check: with V̄_k the mean slip velocity over the analysed samples
// in contact (models/contact.h: V = ωR + tᵀḋ), R_k ω the rotor's surface speed, ε the tanh law's
// velocity scale and f_roll,k = RCI_k·ω/2π the backward precession at which contact k rolls,
//   whirl (rolls)  ⇔  |V̄_k| ≤ max(rolling_slip_tolerance · R_k ω, rolling_micro_slip · ε)
//                     and  |BP − f_roll,k| ≤ whirl_tolerance · f_roll,k.
// For a circular orbit both sides measure the same thing (V = ωR − Ω(C + δ), so |V|/(ωR) ≈
// |1 − BP/f_roll|), but the slip is measured directly and the precession is read off a spectral
// peak; they part where a whip locks next to the rolling line (case C(a) at 48 rpm: BP 79.18 Hz,
// 1.0 % below rolling, yet slipping at 1.0 % of ωR) or where the precession sits on the rolling
// line while the contact slips back and forth (C(a)'s left contact at 132 rpm, 22 % in contact:
// BP 0.25 % from rolling, mean slip 8.6 % of ωR).
enum class RubRegime {
  kUnknown,    // the integration failed at this speed
  kNoContact,  // the contact did not touch in the analysed time, or shows no backward precession
  // The contact touched, for less than min_contact_fraction of the analysed time (impacts,
  // grazing): too little contact for rolling or slipping to mean anything. Its BP (the spectrum of
  // the relative motion over the whole stretch) and its slip velocity (over its contact time) are
  // measured and kept; for the jumps it counts as contact lost, like kNoContact.
  kIntermittent,
  kWhirl,      // the contact rolls: small slip and BP on the rolling line (above)
  kWhip,       // otherwise: the contact slips (BP locked elsewhere, usually below f_roll,k)
};
const char* ToString(RubRegime regime);
// The regime whose ToString is `name`; nothing when no regime has that name.
std::optional<RubRegime> RubRegimeNamed(const std::string& name);

struct RubRegimeOptions {
  // Largest mean slip |V̄_k|, as a share of the surface speed R_k ω, of a rolling contact. In
  // (0, 1). Measured over the nine thesis sweeps (docs/studies/sweeps.md; ε = 1e-3
  // m/s, settled speeds in full contact): where both contacts roll they slip by at most 0.27 % of
  // ωR (0.46ε; B(a) at 48 rpm, C(c) at 40 rpm), the whips by at least 0.97 % (1.85ε: the 79.2 Hz
  // whip of C(a), C(b), C(c) at 48 rpm, 1 % below rolling at 80 Hz). 0.5 % lies in that gap,
  // about 2× above the one and 2× below the other. Inside it fall only states whose slip changes
  // continuously or is modulated (A(b)'s left contact at 36–40 rpm, C(a)'s left at 140–152 rpm
  // while the right whips); their label depends on this value.
  double rolling_slip_tolerance = 0.005;
  // The regularized law's share, in units of its ε: a contact with |V̄_k| ≤ this·ε rolls whatever
  // the surface speed. ≥ 0 (0: the surface-speed rule alone). The tanh law rolls with a
  // micro-slip V = ε·atanh(μ_req/μ), independent of the speed: ≤ ε while μ_req ≤ tanh(1)·μ =
  // 0.76 μ. Below about 50 rpm (ε = 1e-3 m/s, R = 38.1 mm) 0.5 % of ωR is less than ε, and such a
  // whirl would read as whip: case B(b)'s right contact at 20 rpm rolls with V = 0.44ε = 0.56 %
  // of ωR (BP 0.6 % below its rolling line, the other contact slipping by 24 %). ε is 2.2× the
  // two-rolling-contact whirls' 0.46ε and about half the whips' 1.85ε.
  double rolling_micro_slip = 1.0;
  // The frequency check: largest relative distance |BP − f_roll|/f_roll of a rolling contact.
  // In [0, 1). The rolling contacts of the thesis sweeps lie within 0.56 % of rolling; a contact
  // barely in touch can slip little on average and still precess far off the line (C(a)'s left
  // contact at 188–204 rpm, 2 % in contact: 8–19 % off), which this check calls whip.
  double whirl_tolerance = 0.02;
  // A jump within one regime: between successive speeds the precession moves by more than this
  // from both trends, whip-like (BP constant) and whirl-like (BP ∝ ω). > 0. The thesis's whip
  // frequency wanders by < 2 Hz between speeds (82.6 → 83 → 84.66 Hz, case B(a)); whirl-like
  // precession at unequal RCIs (both contacts slipping) follows BP ∝ ω without counting as jumps.
  double frequency_jump_hz = 3.0;
  // Below this share of the analysed time in contact (and above 0), the contact is intermittent
  // (RubRegime::kIntermittent). In [0, 1].
  double min_contact_fraction = 0.01;
  // Largest penetration δ_k of a speed that can be trusted, as a share of the contact's clearance
  // C_k. > 0. The contact laws are those of a small overlap (δ ≪ C): on the thesis's stiff contact
  // δ ≈ N/k1 ≈ 2e-8 m at N = 3 kN, 5e-5 of C. A soft contact (k1 = 3e6 N/m on A(a)'s whirl: the
  // test in tests/sweeps/rub_sweep_test.cpp) or an integration that lets the rotor sink into the
  // stator gives a state that may look settled; a speed whose maximum penetration passes this is
  // untrusted: its regime is still read off it, RubSweepRegimes::untrusted says why, and every
  // jump from or to it is marked (RubSweepJump::trusted).
  double max_penetration = 0.1;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const RubRegimeOptions& options);

enum class RubJumpKind {
  kWhirlToWhip,
  kWhipToWhirl,
  kContactLost,      // whirl or whip → no contact or intermittent contact
  kContactRegained,  // no contact or intermittent contact → whirl or whip
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
  // Neither speed is untrusted (RubRegimeOptions::max_penetration).
  bool trusted = true;
};

struct RubSweepRegimes {
  std::vector<std::vector<RubRegime>> regime;       // [contact][point]
  std::vector<std::vector<double>> precession_hz;   // [contact][point]: BP > 0 backward; NaN: none
  std::vector<std::vector<double>> slip_ratio;      // [contact][point]: |V̄_k|/(R_k ω); NaN: no contact
  std::vector<RubSweepJump> jumps;                  // in schedule order, then by contact
  // [point]: why the speed's integration is not to be trusted ("" when it is, or when its
  // penetration was not recorded: files made before the measure existed).
  std::vector<std::string> untrusted;
};

// Reads regimes and jumps off a sweep of the rub model (parameter ω in rad/s). Every point that
// did not fail needs the slip-velocity measure (RubSweepObservables) on each channel; throws
// std::invalid_argument otherwise.
RubSweepRegimes ClassifySweep(const RubStructure& structure, const std::vector<SweepPoint>& points,
                              const RubRegimeOptions& options = {});

// How long an ensemble's copies (sweeps/ensemble.h) take to reach a target: for each copy, its
// points classified as a sweep (ClassifySweep); the copy reaches the target at the end of the first
// point in which every contact is there (ArrivalContacts::kEvery; e.g. kWhirl: the end of a whip),
// any contact (kAny: a rotor with unequal clearances lands from its whip on a state where one contact
// rolls and the other slips), or the contact `contact` (kOne: the other contact is elsewhere all
// along). A contact is there when it is in `regime`, or, when `precession_above_hz` is finite, when
// its backward precession exceeds that (a whip that ends on a state the regime rules still call
// whip: the unequal-clearance cases' whip at 80–85 Hz lands at 250–400 Hz, slipping). The copies'
// points are consecutive stretches of one run, so the time is the sum of their simulated times.
enum class ArrivalContacts { kEvery, kAny, kOne };
struct ArrivalTarget {
  RubRegime regime = RubRegime::kWhirl;
  double precession_above_hz = kNaN;  // finite: by precession
  ArrivalContacts contacts = ArrivalContacts::kEvery;
  int contact = -1;  // kOne: the index into RubStructure::contacts
};
// "whirl on every contact", "precession above 150 Hz on the right contact", ...
std::string Describe(const RubStructure& structure, const ArrivalTarget& target);
struct RubArrival {
  bool reached = false;  // false: not within the run (censored at `simulated`), or failed
  bool failed = false;   // the copy's integration failed (its points end with the failure)
  double time = kNaN;  // [s] when reached
  int point = -1;          // the index of the copy's point (stretch) in which it was reached
  double simulated = 0.0;  // [s] the copy's whole run
  RubSweepRegimes regimes;  // of the copy's points
  // Why the copy is untrusted (RubSweepRegimes::untrusted of its first such point up to and
  // including the one it arrived in, or over its whole run if it did not), or "".
  std::string untrusted;
};
std::vector<RubArrival> RubArrivals(const RubStructure& structure,
                                    const std::vector<EnsembleCopy>& copies, const ArrivalTarget& target,
                                    const RubRegimeOptions& options = {});
// Whether the classified point `point` of `regimes` is at the target (the rule of RubArrivals;
// target.contact must be a contact of theirs for ArrivalContacts::kOne).
bool Arrived(const RubSweepRegimes& regimes, std::size_t point, const ArrivalTarget& target);

// The rub's Poincaré section for MeasureAttractor (sweeps/attractor.h), in two steps.
// RubPenetrations: the signals are the contacts' penetrations δ_k, sampled every `interval`
// seconds. The stiff contact oscillates at ~20 kHz (√(k/m)) on top of the modulation, also at the
// maxima: sampled every 20 µs (2.3 samples per period) the maxima of A(a)'s periodic whip at
// 80 rpm scattered by 71 N of 3108 N from modulation to modulation, every 2 µs by 13 N. The
// function evaluates the contacts through `system`, which must outlive the section.
// RubSectionMaxima: of their extrema, one point per excursion of δ_k above the level
// max(0, (min δ_k + max δ_k)/2) over the record — the largest maximum in it (ExcursionMaxima).
// In full contact that is one point per modulation of the orbit's radius; in an impacting whip one
// per impact (each contact, δ > 0). Local maxima that do not reach across the level (the contact's
// own ~20 kHz oscillation rides on the modulation) are not points of the section. The normal
// force there is the elastic one (δ̇ = 0).
SampledSection RubPenetrations(RubFixedFrame& system, double interval);

struct RubSectionPoint {
  int contact = 0;
  double t = 0.0;            // from the start of the counted record
  double penetration = 0.0;  // δ_k [m]
  double normal_force = 0.0;  // N_k [N]
};

// Evaluates the extrema's (interpolated) states at `system`'s current parameter.
std::vector<RubSectionPoint> RubSectionMaxima(RubFixedFrame& system,
                                              const std::vector<SectionExtremum>& extrema);

// Why a record whose section is `points` is untrusted, or "": its deepest maximum passes
// `max_penetration` × the contact's clearance (RubRegimeOptions::max_penetration, the sweeps' rule).
std::string UntrustedSection(const RubStructure& structure,
                             const std::vector<RubSectionPoint>& points, double max_penetration);

// The period of the rub's section in returns (SectionPeriod of each contact's normal forces at
// the maxima, to kRubSectionTolerance of their mean, up to 8 returns; the largest over the contacts),
// 0 when a contact's is none or there are no points. The tolerance is what the section resolves:
// sampled every 2 µs, the maxima of A(a)'s periodic whip at 80 rpm scatter by 0.4 % (13 N of 3108
// N, rtol 1e-7; see RubPenetrations): a period-2 orbit or a torus whose section spreads less than
// 1 % is not told from a periodic orbit by the section.
constexpr double kRubSectionTolerance = 0.01;
int RubSectionPeriod(const RubStructure& structure, const std::vector<RubSectionPoint>& section);

// What the motion is, read off its exponents (the largest k of MeasureAttractor) and the period p
// of its section (RubSectionPeriod), in the fixed frame of a rotor without imbalance, whose
// symmetries are time shifts and rotations:
//   a positive exponent, no period p        chaotic
//   a positive exponent and a period p      unsettled (a periodic section yet a positive
//                                           exponent: the record holds a transient)
//   no zero exponent                        an equilibrium (the centred rotor, out of contact)
//   1 zero exponent, the rest negative      a rotating wave (a circular orbit: the rotation is the
//                                           time shift)
//   2 zero exponents                        a relative periodic orbit (one modulation frequency),
//                                           "period p in the section" when p > 1
//   3 zero exponents and a period p         a relative periodic orbit near a bifurcation (a
//                                           multiplier near 1 makes a third exponent ≈ 0)
//   3 zero exponents, no period             a relative 2-torus (two modulation frequencies)
//   all k exponents zero                    "≥ k frequencies": more exponents are needed
// With imbalance the rotation is a symmetry only together with a time shift: one zero fewer for
// each (a synchronous orbit has 1, one modulation frequency 2, ...), named by frequency count.
std::string RubMotion(const RubStructure& structure, const AttractorResult& result,
                      const std::vector<RubSectionPoint>& section);

}  // namespace rubcont

