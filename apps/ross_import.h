// A rotor from ROSS (petrobras/ross, the Python rotordynamics library) as a listed rotor of a
// scene: `rubcont scene import-ross ROSS.toml --base SCENE --contact-stations L R`.
//
// The file is what `ross.Rotor.save(file)` writes (ROSS 1.x–2.x, read from its source:
// rotor_assembly.py Rotor.save, element.py Element.save): a top-level `ross_version` and
// `[parameters]`, then one table per element named "<Class>_<tag>" holding its constructor's
// arguments:
//   ShaftElement  L, idl, odl, idr, odr, n (its left node), material = {name, rho, E, G_s,
//                 [Poisson]}, axial_force, torque, shear_effects, rotary_inertia, gyroscopic,
//                 shear_method_calc, [alpha, beta]
//   DiskElement   n, m, Id, Ip
//   PointMass     n, m or mx, my
//   BearingElement, SealElement  n, kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx, mxx, myy, mxy, myx,
//                 kzz, czz, mzz (each a number or a list over `frequency`), [frequency], [n_link]
// Each becomes a row of the house: a shaft element a [[flexible.rotor_shaft]] row of one element
// (L, odl, idl, E, G_s, rho), a disk or point mass a [[flexible.rotor_disks]] row (station n; m,
// Id, Ip), a bearing or seal a [[flexible.rotor_supports]] row (station n; kxx, cxx). What the
// house's isotropic Timoshenko model cannot represent is refused, naming the element and the rule:
// tapered elements (idl ≠ idr or odl ≠ odr), anisotropic supports (kxx ≠ kyy, cxx ≠ cyy, mx ≠ my),
// cross-coupling (kxy, kyx, cxy, cyx ≠ 0), coefficients that vary with frequency, bearing mass
// (mxx, myy, mxy, myx ≠ 0), bearings linked to another node (n_link), axial load or torque,
// proportional damping (alpha, beta ≠ 0), an element without shear, rotary inertia or gyroscopic
// effects or with a shear coefficient other than Cowper's, and any other element class. The axial
// coefficients (kzz, czz, mzz) are left out: the model is lateral.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "apps/scene.h"

namespace rubcont {

struct RossRotor {
  std::string version;               // ross_version ("unknown" if absent)
  std::vector<ShaftRow> shaft;       // one row per shaft element, by n
  std::vector<Disk> disks;           // DiskElement and PointMass, by node
  std::vector<SupportRow> supports;  // BearingElement and SealElement, by node
};

// Reads a ROSS rotor file. Throws std::invalid_argument naming the file, the element (its table
// "<Class>_<tag>"), the key and the rule for anything the rows cannot hold (above).
RossRotor ReadRossRotor(const std::filesystem::path& file);

struct ImportRossRequest {
  std::string ross_file;
  std::string base_scene;   // a two_point scene: the stator, contacts and analysis kept
  std::array<int, 2> contact_stations{0, 0};  // ROSS nodes of the left and right contacts
  std::optional<std::string> out_file;        // the scene written here (else printed on `out`)
};

// The base scene with its rotor replaced by the ROSS rotor, listed; its [rotor] rigid data
// from the rows; stage "analytic" left out if the rotor has bearings. The scene is checked by
// loading it (exit 2 with every problem); then printed or written atomically. Exit codes as
// every command's.
int ImportRossCommand(const ImportRossRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
