/* greybox C ABI — friction laws for FE user routines.
 *
 * Load a law once (law file, model file from `greybox fit`, or table), evaluate mu(p, v, T)
 * for batches of contact states from any number of threads, free it.
 * Units: pressure Pa, sliding velocity m/s, temperature K.
 * Every function returns GREYBOX_OK (0) or an error code; greybox_last_error() gives the
 * calling thread's last message. Outputs are written only on success (GREYBOX_ERR_MU: set
 * to NaN). No call allocates on the evaluation path.
 *
 * Lengths: greybox_law_eval takes each array with its length and refuses an array shorter
 * than the batch (GREYBOX_ERR_LENGTH) before anything is read or written, so a wrong count
 * never reads or writes past the caller's arrays. greybox_law_mu and greybox_law_mu_grad take
 * one count for every array and remain for existing callers.
 *
 * Every mu the law gives is checked against the possible range 0..3 (the physics table) and
 * every derivative to be finite: a law broken between the checks made at load returns
 * GREYBOX_ERR_MU naming the state. */
#ifndef GREYBOX_H
#define GREYBOX_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GREYBOX_OK 0
#define GREYBOX_ERR_NULL 1  /* a required pointer was null */
#define GREYBOX_ERR_LOAD 2  /* the file could not be read or is not a valid law */
#define GREYBOX_ERR_INPUT 3 /* NaN/inf or negative pressure/temperature in the inputs */
#define GREYBOX_ERR_PANIC 4 /* internal error caught at the boundary */
#define GREYBOX_ERR_LENGTH 5 /* an array shorter than the batch n (nothing read or written) */
#define GREYBOX_ERR_MU 6     /* the law gave mu outside 0..3 or a non-finite derivative (outputs NaN) */

typedef struct GreyboxLaw GreyboxLaw;

int32_t greybox_law_load(const char *path, GreyboxLaw **out);
void greybox_law_free(GreyboxLaw *law);

/* mu[i] for (pressure_pa[i], velocity_m_s[i], temperature_k[i]); temperature_k may be NULL. */
int32_t greybox_law_mu(const GreyboxLaw *law, size_t n, const double *pressure_pa, const double *velocity_m_s,
                       const double *temperature_k, double *mu);

/* As greybox_law_mu, plus derivatives where the pointers are non-NULL:
 * dmu_dp [1/Pa], dmu_dv [s/m], dmu_dt [1/K] (central differences). */
int32_t greybox_law_mu_grad(const GreyboxLaw *law, size_t n, const double *pressure_pa, const double *velocity_m_s,
                            const double *temperature_k, double *mu, double *dmu_dp, double *dmu_dv, double *dmu_dt);

/* mu and, where the output pointers are non-NULL, its derivatives for n states, each array
 * with its length (values it holds); temperature_k may be NULL (room temperature; its length
 * is then ignored). An array shorter than n: GREYBOX_ERR_LENGTH, nothing read or written. */
int32_t greybox_law_eval(const GreyboxLaw *law, size_t n, const double *pressure_pa, size_t pressure_len,
                         const double *velocity_m_s, size_t velocity_len, const double *temperature_k,
                         size_t temperature_len, double *mu, size_t mu_len, double *dmu_dp, size_t dmu_dp_len,
                         double *dmu_dv, size_t dmu_dv_len, double *dmu_dt, size_t dmu_dt_len);

/* Copies the last error message of the calling thread (NUL-terminated, truncated to len);
 * returns its full length. */
size_t greybox_last_error(char *buf, size_t len);

const char *greybox_version(void);

#ifdef __cplusplus
}
#endif
#endif
