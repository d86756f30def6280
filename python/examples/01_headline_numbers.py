"""The README's headline numbers (its "What it is" section), recomputed from Python, cell by cell.

    python python/examples/01_headline_numbers.py      # from the repository root

Each figure is printed with the README's wording and rounding, and checked against it: the script
fails if a number the README states is not what the library computes.
"""

import warnings

import catflip

warnings.simplefilter("ignore", catflip.CatflipWarning)  # the paper's θ = 45° is outside its own range
checks = []


def show(what, value, fmt, readme):
    text = format(value, fmt)
    print(f"{what:<58} {text:>16}   (README: {readme})")
    checks.append((what, text, readme))


# %% The paper's worked example: the published schedule, through the exact engine.
paper = catflip.load("problems/paper.toml")
m = catflip.simulate(paper)
show("published schedule: twist, deg", m.twist_deg, ".2f", "-174.07")
show("published schedule: swing, deg", m.swing_deg, ".2f", "0.59")
show("published schedule: exact peak torque, N·m", m.peak_torque_nm, ".1f", "66.5")
show("paper's circulation π/C, rad", m.report["circulation_rad"], ".4f", "3.2250")

# %% The optimisers: calibration, profile QP + exact refinement, retiming of every phase.
opt = catflip.optimize(paper).report
show("calibrated circulation (twist exactly 180°), rad", opt["calibration"]["circulation"], ".4f", "3.3366")
show("best classic profile: twist-phase peak, N·m", opt["best_library"][1], ".1f", "37.4")
twist_peaks = opt["refined_optimum"]["evaluation"]["exact_peak_nm"]["twist"]
show("exact-dynamics optimum: twist-phase peak, N·m", max(twist_peaks), ".3f", "5.824")
show("every phase retimed: whole manoeuvre's peak, N·m", opt["all_phases"]["evaluation"]["exact_peak_nm"]["max"], ".2f", "9.80")

# %% A gentler cone-path flip.
cone = catflip.simulate(catflip.load("problems/cone-calibrated.toml"))
show("cone-calibrated: twist, deg", abs(cone.twist_deg), ".6f", "180.000000")
show("cone-calibrated: swing, deg", cone.swing_deg, ".2f", "0.07")
show("cone-calibrated: peak torque, N·m", cone.peak_torque_nm, ".1f", "8.0")

# %% The whole-manoeuvre optimum: both joint paths over the whole fall.
whole = catflip.optimize_whole(paper)
w = whole.report
show("whole optimum: largest bend, deg", w["max_bend_deg"], ".1f", "46.8")
show("whole optimum: twist, deg", w["twist_deg"], ".9f", "-180.000000000")
show("whole optimum: peak motor torque, N·m", w["peak_torque_nm"]["max"], ".4f", "0.3165")
show("whole optimum: swing, deg", w["swing_deg"], ".1e", "2.9e-13")
print(f"whole optimum: its time series has {len(whole.series.t)} rows")

wrong = [(what, text, readme) for what, text, readme in checks if text != readme]
for what, text, readme in wrong:
    print(f"MISMATCH {what}: computed {text}, README says {readme}")
assert not wrong, f"{len(wrong)} headline numbers differ from the README"
print(f"all {len(checks)} headline numbers agree with the README")
