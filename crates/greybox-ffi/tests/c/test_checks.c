/* The checked C ABI: each array with its length, and the law's mu checked.
 * Usage: test_checks LAW BROKEN_LAW
 *   LAW        a sound law: greybox_law_eval with the right lengths is OK, with an array
 *              shorter than n refused (GREYBOX_ERR_LENGTH) with nothing written;
 *   BROKEN_LAW a law that gives mu outside 0..3 at the second state: GREYBOX_ERR_MU naming
 *              it, every output NaN. Prints "checks-failed N". */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "greybox.h"

static int expect(int got, int want, const char *what, const char *needle) {
    char msg[512];
    greybox_last_error(msg, sizeof msg);
    if (got != want || (needle && strstr(msg, needle) == NULL)) {
        printf("FAILED %s: status %d (want %d), message: %s\n", what, got, want, msg);
        return 1;
    }
    printf("ok %s: %s\n", what, got == GREYBOX_OK ? "" : msg);
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 3) return 2;
    GreyboxLaw *law = NULL, *broken = NULL;
    if (greybox_law_load(argv[1], &law) != GREYBOX_OK) return 1;
    if (greybox_law_load(argv[2], &broken) != GREYBOX_OK) {
        char msg[512];
        greybox_last_error(msg, sizeof msg);
        printf("broken law refused at load: %s\n", msg);
        return 1;
    }
    int fails = 0;
    double p[3] = {1.0e9, 1.5e9, 2.0e9}, v[3] = {0.5, 1.5, 3.5}, t[3] = {293.15, 293.15, 293.15};
    double mu[3] = {42, 42, 42}, dp[3], dv[3], dt[3];
    fails += expect(greybox_law_eval(law, 3, p, 3, v, 3, t, 3, mu, 3, dp, 3, dv, 3, dt, 3), GREYBOX_OK,
                    "right lengths", NULL);
    /* a count one larger than the velocity array: refused, nothing written */
    double mu2[3] = {42, 42, 42};
    fails += expect(greybox_law_eval(law, 3, p, 3, v, 2, t, 3, mu2, 3, NULL, 0, NULL, 0, NULL, 0),
                    GREYBOX_ERR_LENGTH, "short velocity", "velocity_m_s holds 2 values");
    if (mu2[0] != 42 || mu2[2] != 42) { printf("FAILED: outputs written on a length error\n"); fails++; }
    fails += expect(greybox_law_eval(law, 3, p, 3, v, 3, t, 3, mu2, 1, NULL, 0, NULL, 0, NULL, 0),
                    GREYBOX_ERR_LENGTH, "short mu", "mu holds 1 values");
    fails += expect(greybox_law_eval(law, 3, p, 3, v, 3, t, 3, mu2, 3, dp, 3, dv, 2, NULL, 0),
                    GREYBOX_ERR_LENGTH, "short derivative", "dmu_dv holds 2");
    /* a NULL temperature has no length to check */
    fails += expect(greybox_law_eval(law, 3, p, 3, v, 3, NULL, 0, mu2, 3, NULL, 0, NULL, 0, NULL, 0),
                    GREYBOX_OK, "null temperature", NULL);
    /* the broken law: mu beyond 0..3 at state 1 */
    double bp[2] = {1.0e9, 1.0e9}, bv[2] = {1.0, 1.0e-3}, bmu[2] = {42, 42};
    fails += expect(greybox_law_eval(broken, 2, bp, 2, bv, 2, NULL, 0, bmu, 2, NULL, 0, NULL, 0, NULL, 0),
                    GREYBOX_ERR_MU, "implausible mu", "state 1");
    if (!isnan(bmu[0]) || !isnan(bmu[1])) { printf("FAILED: outputs not NaN after GREYBOX_ERR_MU\n"); fails++; }
    fails += expect(greybox_law_mu(broken, 2, bp, bv, NULL, bmu), GREYBOX_ERR_MU, "implausible mu (unchecked lengths)",
                    "outside the possible range");
    double zero_v = 0.0;
    fails += expect(greybox_law_mu(broken, 1, bp, &zero_v, NULL, bmu), GREYBOX_ERR_MU, "infinite mu", "state 0");
    printf("checks-failed %d\n", fails);
    greybox_law_free(law);
    greybox_law_free(broken);
    return fails == 0 ? 0 : 1;
}
