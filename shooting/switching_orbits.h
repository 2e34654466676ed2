// Periodic orbits of a piecewise-smooth system (OdeSystem::SwitchingFunctions: contacts that open
// and close) followed across changes of their switching pattern, as pieces:
//
//   - while the orbit crosses no surface, on the options' own mesh (ShootingOptions::mesh, no
//     event boundaries); after every step the orbit is sampled, and the first orbit that crosses
//     a surface ends the piece (grazing: a contact starts to open, or to close);
//   - while it crosses, on its switches (WithEventBoundaries, ShootingOptions::event_boundaries,
//     the start moved to the middle of its longest stretch without a switch so that no switch
//     lies at t = 0): every segment smooth, so a fixed Gauss mesh keeps its order. The piece ends
//     where a phase between two switches shrinks to nothing (an event of the engine, located) —
//     the pattern changes there, and the next piece starts on the options' mesh from that orbit,
//     in the direction of λ the piece was going (at a grazing point the orbits on the other side
//     of it have the other pattern), and becomes a piece on switches again at once if the orbit
//     still crosses — or where, sampled after a step, the orbit switches more often than its
//     boundaries do (a new phase opened inside a segment: a contact that flickers open), and the
//     next piece starts on the switches of that orbit.
//
// Any other end of a piece (the range, the step limit, a failure, a user's on_step returning false)
// ends the family. Use:
//     SwitchingOrbitOptions options;
//     options.family.lambda_min = 0.5;  options.family.lambda_max = 2.0;
//     options.family.shooting.integrator.method = IntegrationMethod::kGaussCollocation;
//     const SwitchingOrbitFamily f = ContinueAcrossSwitches(system, OrbitKind::kAutonomous, start,
//                                                           options);
//     // f.pieces[k].family.branch, f.pieces[k].switches, f.pieces[k].end
#pragma once

#include <string>
#include <vector>

#include "shooting/orbit_branches.h"

namespace rubcont {

struct SwitchingOrbitOptions {
  // The range, the engine, measures, tests and on_step; family.shooting is the mesh of the pieces
  // that cross no surface and must have no event boundaries.
  PeriodicOrbitBranchOptions family;
  int direction = +1;   // of λ from the start
  int max_pieces = 8;   // pieces at most (≥ 1)
  int samples = 8192;   // per period, where the switches are looked for (WithEventBoundaries)
};

// Throws std::invalid_argument naming the field.
void Validate(const SwitchingOrbitOptions& options);

struct SwitchingOrbitPiece {
  PeriodicOrbitBranch family;  // its shooting: the options' mesh, or the switches
  int switches = 0;            // segment boundaries on switching surfaces (0: the options' mesh)
  std::string end;             // how it ended and what followed
};

struct SwitchingOrbitFamily {
  std::vector<SwitchingOrbitPiece> pieces;  // in order along the family
  std::string message;                      // how the family ended
  ShootingStatistics work;                  // all pieces
};

// Autonomous and relative kinds (pieces on switches need them). Throws std::invalid_argument for
// an invalid start or options; numerical ends are statuses of the last piece and the message.
SwitchingOrbitFamily ContinueAcrossSwitches(OdeSystem& system, OrbitKind kind,
                                            const OrbitStart& start,
                                            const SwitchingOrbitOptions& options);

}  // namespace rubcont
