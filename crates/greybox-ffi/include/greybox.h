/* greybox C ABI — friction laws for FE user routines.
 *
 * Load a law once (law file, model file from `greybox fit`, or table), evaluate mu(p, v, T)
 * for batches of contact states from any number of threads, free it.
 * Units: pressure Pa, sliding velocity m/s, temperature K.
 * Every function returns GREYBOX_OK (0) or an error code; greybox_last_error() gives the
 * calling thread's last message. Outputs are written only on success. No call allocates on
 * the evaluation path. */
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

/* Copies the last error message of the calling thread (NUL-terminated, truncated to len);
 * returns its full length. */
size_t greybox_last_error(char *buf, size_t len);

const char *greybox_version(void);

#ifdef __cplusplus
}
#endif
#endif
