"""Layout of the hybrid state shared by the system builder and the numba kernels.

The continuous state is ``z = [u_l, du_l, w_b, dw_b, x, dx, sin wt, cos wt, 1]``: the two
modal coordinates and the slider, each with its velocity, plus the drive phase and a constant,
so that every mode of the switch model is a *linear time-invariant* system ``dz/dt = A z``
(exactly integrable with a matrix exponential) and every switching condition is a zero of a
linear functional ``h . z``.

The discrete state (the "mode") is ``contact * 9 + tip * 3 + guide`` with

* ``contact``: 0 separated (F_N = 0), 1 in contact;
* ``tip``: 0 stick (v_rel = 0), 1 slip with v_rel > 0, 2 slip with v_rel < 0
  (meaningless while separated, kept at 1);
* ``guide``: 0 slider held by the linear guide's static friction (dx = 0; in tip stick the
  tip is then held too, which freezes the B2 coordinate), 1 slider moving forward (dx > 0),
  2 slider moving backward.
"""

from __future__ import annotations

N_STATE = 9
U, DU, W, DW, X, DX, SIN, COS, ONE = range(9)

N_MODES = 18
MAX_EVENTS = 5
N_FUNCS = 7

# rows of the mode-independent functional bank: normal force, guide normal load in contact,
# relative velocity, tangential force that holds tip and slider at rest, stick force with
# the slider moving forward / backward (row F_HOLD + guide), guide load when separated
F_FN, F_NG_CONTACT, F_VREL, F_HOLD, F_FS1, F_FS2, F_NG_SEP = range(N_FUNCS)

SEPARATED, CONTACT = 0, 1
STICK, SLIP_POS, SLIP_NEG = 0, 1, 2
HELD, FORWARD, BACKWARD = 0, 1, 2

# event types (switching surfaces)
EV_NONE = -1
EV_SEPARATE = 1
EV_CONTACT = 2
EV_VREL_ZERO = 3
EV_STICK_BREAK = 4
EV_XDOT_ZERO = 5
EV_GUIDE_RELEASE = 6

# phase codes reported in traces
PHASE_STICK, PHASE_SLIP_POS, PHASE_SLIP_NEG, PHASE_SEPARATION = 0, 1, 2, 3

# status codes returned by the kernel
OK = 0
ERR_CHATTER = 1


def mode_index(contact: int, tip: int, guide: int) -> int:
    """Encode a discrete mode as an integer in ``range(N_MODES)``."""
    return contact * 9 + tip * 3 + guide


# entries of the scalar parameter vector handed to the kernels
(SC_MU_S, SC_MU_D, SC_MU_SD, SC_PHI_LL, SC_GAMMA_N, SC_GAMMA_T, SC_ALV, SC_ABV, SC_C_L,
 SC_C_B, SC_M_L, SC_K_L, SC_M_B, SC_K_B, SC_M, SC_K, SC_OMEGA, SC_GN_EXCESS, SC_EPS,
 SC_PHI_BL, SC_LOAD) = range(21)
N_SCALARS = 21
