// The absolute tolerance of the ODE wear integrators on the worn depth W (m).
#include <cmath>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "wear_rows.hpp"

namespace fretbem::wear_detail {

// The tolerance is wear.atol when given (expert override), else rtol times the
// indentation of the unworn surface. A fixed metre value carried over from another scenario
// let nodes that just came into contact (W ~ 1e-10 m) set the step: 5757 simulated cycles to
// N = 5e4 at n = 64; the indentation is the depth scale of the end state (Popov:
// d_inf - d_0 is a fraction of d_0) and of gross-slip wear per integrator step.
// A given atol is held to wear.rtol's range relative to that depth scale (it is known only
// after the first normal solve, so `check` cannot refuse it).
double absolute_tolerance(const Model& model, WearCycles& cyc) {
  const WearSpec& w = model.scenario.wear;
  const double delta0 = std::abs(cyc.initial_indentation());
  // Complete contact on a periodic grid (a flat) has no approach (the kernel's mean mode is
  // free), and rtol x 0 is no tolerance: ARKODE's error weights 1 / (rtol |W| + atol) are
  // infinite on the unworn W = 0 (ARK_ILL_INPUT, combination sweep seed 35 case 3).
  if (w.atol <= 0.0 && !(delta0 > 0.0))
    throw InputError(
        "wear.atol: the unworn indentation is 0 (every node touches at once, as a flat on a "
        "periodic grid), so wear.rtol x indentation gives the ODE integrators no absolute "
        "tolerance; give wear.atol in m, or use wear.integrator = cycle");
  if (w.atol <= 0.0) return w.rtol * delta0;
  if (delta0 > 0.0 &&
      !(w.atol >= kMinWearRelTolerance * delta0 && w.atol <= kMaxWearRelTolerance * delta0))
    throw InputError("wear.atol = " + format_number(w.atol) + " m is outside [" +
                     format_number(kMinWearRelTolerance) + ", " +
                     format_number(kMaxWearRelTolerance) + "] x the unworn indentation " +
                     format_number(delta0) +
                     " m: the error control would not hold the worn depth (or ARKODE fails); "
                     "leave wear.atol out to use wear.rtol x that indentation");
  return w.atol;
}

}  // namespace fretbem::wear_detail
