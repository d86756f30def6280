//! Slips of the paper that carry no number of their own.

use super::Note;

/// Every slip found that the entries do not already show, in section order.
pub(super) const NOTES: &[Note] = &[
    Note { section: "§2", text: "Claim 2 refers to \"the I_yy in claim 2\": Claim 1 is meant." },
    Note {
        section: "§2",
        text: "Claim 1 gives the whole cat's L = 2 I_yy ω, but eq. (1) and (2) drop the 2: they are one half's momentum. Eq. (2)'s MR²/4 + ML²/12 is the correct transverse moment, unlike §6.3 and §7.",
    },
    Note {
        section: "§2",
        text: "The halves' axes lie in the y–z plane, so the x → −x symmetry also makes I_xz vanish: x, y and z are all principal (the printed tensor keeps 2 I_xz, which §3 then silently drops).",
    },
    Note {
        section: "§2",
        text: "Axes: y lies in the plane of the bend, perpendicular to the bisector of θ, through both halves' centres (the spine when straight: our z); z is the bisector.",
    },
    Note {
        section: "§3",
        text: "\"So, I_yy > I_xx\" contradicts the inequality I_yy < I_xx just derived; \"sin(θ/2) ≤ cos(θ/2)\" holds only for θ ≤ π/2, while I_yy ≤ I_zz needs sin(θ/2) ≥ cos(θ/2), i.e. π/2 ≤ θ ≤ π (printed \"π ≤ θ ≤ π/2\").",
    },
    Note {
        section: "§3",
        text: "The worked example's θ = π/4 lies outside the paper's own stability range: there I_zz < I_yy < I_xx and y is the intermediate axis.",
    },
    Note {
        section: "§4",
        text: "ω(t) = ω0(1 − cos(πt/T)) keeps the acceleration continuous but ends at 2ω0, not at rest: the rate jumps when unbending starts (an impulse), against the stated aim of continuous angular velocity.",
    },
    Note {
        section: "§5",
        text: "Primes are mixed (\"L''_A\" for L'_A); I_zz here means the axial I_z'z' while §3's I_zz is a bent-cat moment; L_C = I_yy ω_c needs the whole cat's I_yy (twice §2's per-half one).",
    },
    Note {
        section: "§5",
        text: "ω_c = −2 (I_zz/I_yy) sin(θ/2) ω is negative here and positive in §9; the zero-momentum sum is circular, since this ω_c was derived from that very condition.",
    },
    Note {
        section: "§6.3",
        text: "`omega_0 = np.pi / (dt * cloud)`: `cloud` stands for `c`; t_max hard-codes h = 10 and g = 9.8; ix, iy use the slipped m(r² + l²)/12.",
    },
    Note {
        section: "§6.4",
        text: "The bend target (π − θ)/2 · (1 − cos(π/step_2 · (t − step_2))) is shifted by half a period: it starts bent (a step at t = 0) and ends straight; use (1 − cos(π t/step_2)).",
    },
    Note {
        section: "§6.4",
        text: "`targetPositions[...]` lacks its `=`; `dt_3`, `x`, `y`, `fps`, `phi`, `t` and `i` are never defined (dt_3 = t_max − step_3; x, y the end-of-twist targets); the unbend line closes one `]` too many.",
    },
    Note {
        section: "§6.4",
        text: "As printed, `t += 1.0 / fps` and `i += 1` are indented under the last branch, so time never advances while t < step_3 and the loop never ends.",
    },
    Note {
        section: "§7",
        text: "\"Maximum angle of bend θ = π/4\": θ is the angle between the halves, so the bend is β = π − θ = 3π/4; gravity is quoted as −9.8 and used as 9.8.",
    },
    Note {
        section: "§8",
        text: "\"Intwisting\" is the unbending; θ1 and θ3 are joint angles of the bend, not the angle θ between the halves; §8's I* = I_x'x' + md² is right where §7 wrote md.",
    },
    Note {
        section: "§8",
        text: "The bounds treat each phase as one link turning about the joint with inertia I*: they ignore the centripetal φ̇² terms, the coupling of the two joints and the base's motion; the exact inverse dynamics settles the torques.",
    },
];
