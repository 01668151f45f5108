/* generated, do not edit: registry of walker's generated C kernels
 * (wk_kernel_table, declared in walker/_core/wk_models.h), one entry per kernel of
 * walker/_generated/<module>.c;
 * regenerate with `python scripts/generate_kernels.py`. */
#include <stddef.h>

#include "wk_models.h"
#include "simplest.h"
#include "compass.h"
#include "compass_plain.h"
#include "kneed.h"
#include "kneed_plain.h"
#include "double_pendulum.h"
#include "three_link.h"
#include "five_link.h"

static const wk_kernel_entry KERNELS[] = {
    {"simplest.accel", "qqdp_v", (void *)wk_simplest_accel, 2, 4, {2, 0, 0}},
    {"simplest.daccel_dx", "qqdp_v", (void *)wk_simplest_daccel_dx, 2, 4, {2, 4, 0}},
    {"compass.accel", "qqdp_v", (void *)wk_compass_accel, 2, 10, {2, 0, 0}},
    {"compass.accel_jac", "qqdp_v", (void *)wk_compass_accel_jac, 2, 10, {2, 4, 0}},
    {"compass.mass_matrix", "qp_v", (void *)wk_compass_mass_matrix, 2, 10, {2, 2, 0}},
    {"compass.coriolis", "qqdp_v", (void *)wk_compass_coriolis, 2, 10, {2, 2, 0}},
    {"compass.gravity", "qp_v", (void *)wk_compass_gravity, 2, 10, {2, 0, 0}},
    {"compass.bias", "qqdp_v", (void *)wk_compass_bias, 2, 10, {2, 0, 0}},
    {"compass.forcing", "qqdp_v", (void *)wk_compass_forcing, 2, 10, {2, 0, 0}},
    {"compass.dmass", "qp_v", (void *)wk_compass_dmass, 2, 10, {2, 2, 2}},
    {"compass.dbias_dq", "qqdp_v", (void *)wk_compass_dbias_dq, 2, 10, {2, 2, 0}},
    {"compass.dbias_dqd", "qqdp_v", (void *)wk_compass_dbias_dqd, 2, 10, {2, 2, 0}},
    {"compass.kinetic", "qqdp_s", (void *)wk_compass_kinetic, 2, 10, {0, 0, 0}},
    {"compass.potential", "qp_s", (void *)wk_compass_potential, 2, 10, {0, 0, 0}},
    {"compass.points", "qp_v", (void *)wk_compass_points, 2, 10, {4, 2, 0}},
    {"compass.hip_jac", "qp_v", (void *)wk_compass_hip_jac, 2, 10, {2, 2, 0}},
    {"compass.ext_mass_matrix", "qp_v", (void *)wk_compass_ext_mass_matrix, 4, 10, {4, 4, 0}},
    {"compass.ext_swing_contact_jac", "qp_v", (void *)wk_compass_ext_swing_contact_jac, 4, 10, {2, 4, 0}},
    {"compass.ext_stance_contact_jac", "qp_v", (void *)wk_compass_ext_stance_contact_jac, 4, 10, {2, 4, 0}},
    {"compass/plain.accel", "qqdp_v", (void *)wk_compass_plain_accel, 2, 10, {2, 0, 0}},
    {"compass/plain.accel_jac", "qqdp_v", (void *)wk_compass_plain_accel_jac, 2, 10, {2, 4, 0}},
    {"compass/plain.accel_and_jac", "qqdp_v", (void *)wk_compass_plain_accel_and_jac, 2, 10, {2, 5, 0}},
    {"compass/plain.mass_matrix", "qp_v", (void *)wk_compass_plain_mass_matrix, 2, 10, {2, 2, 0}},
    {"compass/plain.points", "qp_v", (void *)wk_compass_plain_points, 2, 10, {4, 2, 0}},
    {"compass/plain.hip_jac", "qp_v", (void *)wk_compass_plain_hip_jac, 2, 10, {2, 2, 0}},
    {"compass/plain.ext_mass_matrix", "qp_v", (void *)wk_compass_plain_ext_mass_matrix, 4, 10, {4, 4, 0}},
    {"compass/plain.ext_swing_contact_jac", "qp_v", (void *)wk_compass_plain_ext_swing_contact_jac, 4, 10, {2, 4, 0}},
    {"compass/plain.ext_stance_contact_jac", "qp_v", (void *)wk_compass_plain_ext_stance_contact_jac, 4, 10, {2, 4, 0}},
    {"kneed.unlocked_accel", "qqdp_v", (void *)wk_kneed_unlocked_accel, 3, 17, {3, 0, 0}},
    {"kneed.unlocked_accel_jac", "qqdp_v", (void *)wk_kneed_unlocked_accel_jac, 3, 17, {3, 6, 0}},
    {"kneed.unlocked_mass_matrix", "qp_v", (void *)wk_kneed_unlocked_mass_matrix, 3, 17, {3, 3, 0}},
    {"kneed.unlocked_coriolis", "qqdp_v", (void *)wk_kneed_unlocked_coriolis, 3, 17, {3, 3, 0}},
    {"kneed.unlocked_gravity", "qp_v", (void *)wk_kneed_unlocked_gravity, 3, 17, {3, 0, 0}},
    {"kneed.unlocked_bias", "qqdp_v", (void *)wk_kneed_unlocked_bias, 3, 17, {3, 0, 0}},
    {"kneed.unlocked_forcing", "qqdp_v", (void *)wk_kneed_unlocked_forcing, 3, 17, {3, 0, 0}},
    {"kneed.unlocked_dmass", "qp_v", (void *)wk_kneed_unlocked_dmass, 3, 17, {3, 3, 3}},
    {"kneed.unlocked_dbias_dq", "qqdp_v", (void *)wk_kneed_unlocked_dbias_dq, 3, 17, {3, 3, 0}},
    {"kneed.unlocked_dbias_dqd", "qqdp_v", (void *)wk_kneed_unlocked_dbias_dqd, 3, 17, {3, 3, 0}},
    {"kneed.unlocked_kinetic", "qqdp_s", (void *)wk_kneed_unlocked_kinetic, 3, 17, {0, 0, 0}},
    {"kneed.unlocked_potential", "qp_s", (void *)wk_kneed_unlocked_potential, 3, 17, {0, 0, 0}},
    {"kneed.unlocked_points", "qp_v", (void *)wk_kneed_unlocked_points, 3, 17, {5, 2, 0}},
    {"kneed.locked_accel", "qqdp_v", (void *)wk_kneed_locked_accel, 2, 17, {2, 0, 0}},
    {"kneed.locked_accel_jac", "qqdp_v", (void *)wk_kneed_locked_accel_jac, 2, 17, {2, 4, 0}},
    {"kneed.locked_mass_matrix", "qp_v", (void *)wk_kneed_locked_mass_matrix, 2, 17, {2, 2, 0}},
    {"kneed.locked_coriolis", "qqdp_v", (void *)wk_kneed_locked_coriolis, 2, 17, {2, 2, 0}},
    {"kneed.locked_gravity", "qp_v", (void *)wk_kneed_locked_gravity, 2, 17, {2, 0, 0}},
    {"kneed.locked_bias", "qqdp_v", (void *)wk_kneed_locked_bias, 2, 17, {2, 0, 0}},
    {"kneed.locked_forcing", "qqdp_v", (void *)wk_kneed_locked_forcing, 2, 17, {2, 0, 0}},
    {"kneed.locked_dmass", "qp_v", (void *)wk_kneed_locked_dmass, 2, 17, {2, 2, 2}},
    {"kneed.locked_dbias_dq", "qqdp_v", (void *)wk_kneed_locked_dbias_dq, 2, 17, {2, 2, 0}},
    {"kneed.locked_dbias_dqd", "qqdp_v", (void *)wk_kneed_locked_dbias_dqd, 2, 17, {2, 2, 0}},
    {"kneed.locked_kinetic", "qqdp_s", (void *)wk_kneed_locked_kinetic, 2, 17, {0, 0, 0}},
    {"kneed.locked_potential", "qp_s", (void *)wk_kneed_locked_potential, 2, 17, {0, 0, 0}},
    {"kneed.locked_points", "qp_v", (void *)wk_kneed_locked_points, 2, 17, {5, 2, 0}},
    {"kneed.locked_hip_jac", "qp_v", (void *)wk_kneed_locked_hip_jac, 2, 17, {2, 2, 0}},
    {"kneed.ext_mass_matrix", "qp_v", (void *)wk_kneed_ext_mass_matrix, 4, 17, {4, 4, 0}},
    {"kneed.ext_swing_contact_jac", "qp_v", (void *)wk_kneed_ext_swing_contact_jac, 4, 17, {2, 4, 0}},
    {"kneed.ext_stance_contact_jac", "qp_v", (void *)wk_kneed_ext_stance_contact_jac, 4, 17, {2, 4, 0}},
    {"kneed/plain.unlocked_accel", "qqdp_v", (void *)wk_kneed_plain_unlocked_accel, 3, 17, {3, 0, 0}},
    {"kneed/plain.unlocked_accel_jac", "qqdp_v", (void *)wk_kneed_plain_unlocked_accel_jac, 3, 17, {3, 6, 0}},
    {"kneed/plain.unlocked_accel_and_jac", "qqdp_v", (void *)wk_kneed_plain_unlocked_accel_and_jac, 3, 17, {3, 7, 0}},
    {"kneed/plain.unlocked_mass_matrix", "qp_v", (void *)wk_kneed_plain_unlocked_mass_matrix, 3, 17, {3, 3, 0}},
    {"kneed/plain.unlocked_points", "qp_v", (void *)wk_kneed_plain_unlocked_points, 3, 17, {5, 2, 0}},
    {"kneed/plain.locked_accel", "qqdp_v", (void *)wk_kneed_plain_locked_accel, 2, 17, {2, 0, 0}},
    {"kneed/plain.locked_accel_jac", "qqdp_v", (void *)wk_kneed_plain_locked_accel_jac, 2, 17, {2, 4, 0}},
    {"kneed/plain.locked_accel_and_jac", "qqdp_v", (void *)wk_kneed_plain_locked_accel_and_jac, 2, 17, {2, 5, 0}},
    {"kneed/plain.locked_mass_matrix", "qp_v", (void *)wk_kneed_plain_locked_mass_matrix, 2, 17, {2, 2, 0}},
    {"kneed/plain.locked_points", "qp_v", (void *)wk_kneed_plain_locked_points, 2, 17, {5, 2, 0}},
    {"kneed/plain.locked_hip_jac", "qp_v", (void *)wk_kneed_plain_locked_hip_jac, 2, 17, {2, 2, 0}},
    {"kneed/plain.ext_mass_matrix", "qp_v", (void *)wk_kneed_plain_ext_mass_matrix, 4, 17, {4, 4, 0}},
    {"kneed/plain.ext_swing_contact_jac", "qp_v", (void *)wk_kneed_plain_ext_swing_contact_jac, 4, 17, {2, 4, 0}},
    {"kneed/plain.ext_stance_contact_jac", "qp_v", (void *)wk_kneed_plain_ext_stance_contact_jac, 4, 17, {2, 4, 0}},
    {"double_pendulum.accel", "qqdp_v", (void *)wk_double_pendulum_accel, 2, 13, {2, 0, 0}},
    {"double_pendulum.accel_jac", "qqdp_v", (void *)wk_double_pendulum_accel_jac, 2, 13, {2, 4, 0}},
    {"double_pendulum.mass_matrix", "qp_v", (void *)wk_double_pendulum_mass_matrix, 2, 13, {2, 2, 0}},
    {"double_pendulum.coriolis", "qqdp_v", (void *)wk_double_pendulum_coriolis, 2, 13, {2, 2, 0}},
    {"double_pendulum.gravity", "qp_v", (void *)wk_double_pendulum_gravity, 2, 13, {2, 0, 0}},
    {"double_pendulum.bias", "qqdp_v", (void *)wk_double_pendulum_bias, 2, 13, {2, 0, 0}},
    {"double_pendulum.forcing", "qqdp_v", (void *)wk_double_pendulum_forcing, 2, 13, {2, 0, 0}},
    {"double_pendulum.dmass", "qp_v", (void *)wk_double_pendulum_dmass, 2, 13, {2, 2, 2}},
    {"double_pendulum.dbias_dq", "qqdp_v", (void *)wk_double_pendulum_dbias_dq, 2, 13, {2, 2, 0}},
    {"double_pendulum.dbias_dqd", "qqdp_v", (void *)wk_double_pendulum_dbias_dqd, 2, 13, {2, 2, 0}},
    {"double_pendulum.kinetic", "qqdp_s", (void *)wk_double_pendulum_kinetic, 2, 13, {0, 0, 0}},
    {"double_pendulum.potential", "qp_s", (void *)wk_double_pendulum_potential, 2, 13, {0, 0, 0}},
    {"double_pendulum.points", "qp_v", (void *)wk_double_pendulum_points, 2, 13, {2, 2, 0}},
    {"three_link.accel", "qqdp_v", (void *)wk_three_link_accel, 3, 11, {3, 0, 0}},
    {"three_link.accel_jac", "qqdp_v", (void *)wk_three_link_accel_jac, 3, 11, {3, 6, 0}},
    {"three_link.mass_matrix", "qp_v", (void *)wk_three_link_mass_matrix, 3, 11, {3, 3, 0}},
    {"three_link.coriolis", "qqdp_v", (void *)wk_three_link_coriolis, 3, 11, {3, 3, 0}},
    {"three_link.gravity", "qp_v", (void *)wk_three_link_gravity, 3, 11, {3, 0, 0}},
    {"three_link.bias", "qqdp_v", (void *)wk_three_link_bias, 3, 11, {3, 0, 0}},
    {"three_link.dmass", "qp_v", (void *)wk_three_link_dmass, 3, 11, {3, 3, 3}},
    {"three_link.dbias_dq", "qqdp_v", (void *)wk_three_link_dbias_dq, 3, 11, {3, 3, 0}},
    {"three_link.dbias_dqd", "qqdp_v", (void *)wk_three_link_dbias_dqd, 3, 11, {3, 3, 0}},
    {"three_link.kinetic", "qqdp_s", (void *)wk_three_link_kinetic, 3, 11, {0, 0, 0}},
    {"three_link.potential", "qp_s", (void *)wk_three_link_potential, 3, 11, {0, 0, 0}},
    {"three_link.points", "qp_v", (void *)wk_three_link_points, 3, 11, {4, 2, 0}},
    {"three_link.hip_jac", "qp_v", (void *)wk_three_link_hip_jac, 3, 11, {2, 3, 0}},
    {"three_link.ground_reaction", "qqdqddp_v", (void *)wk_three_link_ground_reaction, 3, 11, {2, 0, 0}},
    {"three_link.ext_mass_matrix", "qp_v", (void *)wk_three_link_ext_mass_matrix, 5, 11, {5, 5, 0}},
    {"three_link.ext_swing_contact_jac", "qp_v", (void *)wk_three_link_ext_swing_contact_jac, 5, 11, {2, 5, 0}},
    {"three_link.ext_stance_contact_jac", "qp_v", (void *)wk_three_link_ext_stance_contact_jac, 5, 11, {2, 5, 0}},
    {"five_link.accel", "qqdp_v", (void *)wk_five_link_accel, 5, 14, {5, 0, 0}},
    {"five_link.accel_jac", "qqdp_v", (void *)wk_five_link_accel_jac, 5, 14, {5, 10, 0}},
    {"five_link.mass_matrix", "qp_v", (void *)wk_five_link_mass_matrix, 5, 14, {5, 5, 0}},
    {"five_link.coriolis", "qqdp_v", (void *)wk_five_link_coriolis, 5, 14, {5, 5, 0}},
    {"five_link.gravity", "qp_v", (void *)wk_five_link_gravity, 5, 14, {5, 0, 0}},
    {"five_link.bias", "qqdp_v", (void *)wk_five_link_bias, 5, 14, {5, 0, 0}},
    {"five_link.dmass", "qp_v", (void *)wk_five_link_dmass, 5, 14, {5, 5, 5}},
    {"five_link.dbias_dq", "qqdp_v", (void *)wk_five_link_dbias_dq, 5, 14, {5, 5, 0}},
    {"five_link.dbias_dqd", "qqdp_v", (void *)wk_five_link_dbias_dqd, 5, 14, {5, 5, 0}},
    {"five_link.kinetic", "qqdp_s", (void *)wk_five_link_kinetic, 5, 14, {0, 0, 0}},
    {"five_link.potential", "qp_s", (void *)wk_five_link_potential, 5, 14, {0, 0, 0}},
    {"five_link.points", "qp_v", (void *)wk_five_link_points, 5, 14, {6, 2, 0}},
    {"five_link.hip_jac", "qp_v", (void *)wk_five_link_hip_jac, 5, 14, {2, 5, 0}},
    {"five_link.ground_reaction", "qqdqddp_v", (void *)wk_five_link_ground_reaction, 5, 14, {2, 0, 0}},
    {"five_link.ext_mass_matrix", "qp_v", (void *)wk_five_link_ext_mass_matrix, 7, 14, {7, 7, 0}},
    {"five_link.ext_swing_contact_jac", "qp_v", (void *)wk_five_link_ext_swing_contact_jac, 7, 14, {2, 7, 0}},
    {"five_link.ext_stance_contact_jac", "qp_v", (void *)wk_five_link_ext_stance_contact_jac, 7, 14, {2, 7, 0}},
};

static const wk_kernel_hash_entry HASHES[] = {
    {"simplest", WK_SIMPLEST_KERNEL_HASH},
    {"compass", WK_COMPASS_KERNEL_HASH},
    {"compass/plain", WK_COMPASS_PLAIN_KERNEL_HASH},
    {"kneed", WK_KNEED_KERNEL_HASH},
    {"kneed/plain", WK_KNEED_PLAIN_KERNEL_HASH},
    {"double_pendulum", WK_DOUBLE_PENDULUM_KERNEL_HASH},
    {"three_link", WK_THREE_LINK_KERNEL_HASH},
    {"five_link", WK_FIVE_LINK_KERNEL_HASH},
};

const wk_kernel_entry *wk_kernel_table(int64_t *count)
{
    *count = (int64_t)(sizeof(KERNELS) / sizeof(KERNELS[0]));
    return KERNELS;
}

const wk_kernel_hash_entry *wk_kernel_hash_table(int64_t *count)
{
    *count = (int64_t)(sizeof(HASHES) / sizeof(HASHES[0]));
    return HASHES;
}
