"""Case A(a)'s hysteresis loop from Python: the rotating-wave branches computed here (L1, 0.3 s),
the speed-up and speed-down sweeps (L3) read from the committed result file, and the jumps of
the sweeps joined to the bifurcations that explain them.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/hysteresis.py [OUT.png]

(rubcont.sweep(scene) makes the sweeps afresh: 4 to 37 min per direction.)
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import rubcont

scene = rubcont.load_scene("scenes/thesis_A_a.toml")
waves = rubcont.branches(scene)
sweeps = rubcont.read("results/thesis_A_a/sweep.h5")

fig, ax = plt.subplots(figsize=(9, 5.5))
for branch in waves.branches:  # rubcont.Branch: arrays, stability, special points
    speed, hz, stable = branch.speed_rpm, branch.precession_hz, branch.stable
    ax.plot(speed, np.where(stable, hz, np.nan), "C0-", lw=1.5)
    ax.plot(speed, np.where(stable, np.nan, hz), "C3--", lw=0.8)
for direction, marker, color in [("up", "^", "C1"), ("down", "v", "C4")]:
    ax.plot(sweeps[f"sweeps/{direction}/speed_rpm"], sweeps[f"sweeps/{direction}/precession_hz_left"],
            marker, color=color, ms=4, ls="none", label=f"speed-{direction} sweep (L3)")
jumps = "sweeps/jump_table/"
for k, direction in enumerate(sweeps[jumps + "direction"]):
    at = sweeps[jumps + "bifurcation_speed_rpm"][k]
    # The bifurcation on a branch of the sweep file's own (tanh-law) set that explains the jump.
    if sweeps[jumps + "contact"][k] == "left" and np.isfinite(at):
        ax.plot(at, sweeps[jumps + "bifurcation_precession_hz"][k], "ko", mfc="none", ms=10)
        ax.annotate(f"{direction}: {sweeps[jumps + 'bifurcation'][k]}\n{at:.2f} rpm",
                    (at, sweeps[jumps + "bifurcation_precession_hz"][k]), fontsize=7,
                    xytext=(8, -28 if direction == "up" else 12), textcoords="offset points")
ax.plot([], [], "C0-", label="stable rotating waves (L1)")
ax.plot([], [], "C3--", label="unstable rotating waves (L1)")
ax.set(xlabel="running speed [rpm]", ylabel="backward precession at the left contact [Hz]",
       xlim=(20, 260), ylim=(0, 430), title=f"{scene.name}: the hysteresis loop from Python")
ax.legend(loc="upper left", fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "hysteresis_from_python.png", dpi=120)
