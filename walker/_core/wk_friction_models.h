/* Registry entries of walker's models with dry joint friction (walker/friction.py, ported
 * in wk_friction.c): model_compass_coulomb.c, model_double_pendulum.c,
 * model_kneed_coulomb.c, C ports of walker/models/compass_coulomb.py, double_pendulum.py
 * and kneed_coulomb.py.  Their start_phase writes the phase as a double (-1 if a solve is
 * singular, as the numba start_phase returns). */
#ifndef WK_FRICTION_MODELS_H
#define WK_FRICTION_MODELS_H

#include "wk_models.h"

extern const wk_model_entry wk_entry_compass_coulomb;
extern const wk_model_entry wk_entry_double_pendulum;
extern const wk_model_entry wk_entry_kneed_coulomb;

#endif
