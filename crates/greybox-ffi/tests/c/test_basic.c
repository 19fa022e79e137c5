/* Evaluates a law at the points given on the command line and prints mu and the derivatives
 * as C99 hex floats (exact), then checks the error paths. Usage: test_basic LAW P V T [P V T ...] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "greybox.h"

int main(int argc, char **argv) {
    if (argc < 5 || (argc - 2) % 3 != 0) {
        fprintf(stderr, "usage: %s LAW P V T ...\n", argv[0]);
        return 2;
    }
    GreyboxLaw *law = NULL;
    if (greybox_law_load(argv[1], &law) != GREYBOX_OK) {
        char msg[512];
        greybox_last_error(msg, sizeof msg);
        fprintf(stderr, "load failed: %s\n", msg);
        return 1;
    }
    size_t n = (size_t)(argc - 2) / 3;
    double *p = malloc(n * sizeof *p), *v = malloc(n * sizeof *v), *t = malloc(n * sizeof *t);
    double *mu = malloc(n * sizeof *mu), *dp = malloc(n * sizeof *dp), *dv = malloc(n * sizeof *dv), *dt = malloc(n * sizeof *dt);
    for (size_t i = 0; i < n; i++) {
        p[i] = strtod(argv[2 + 3 * i], NULL);
        v[i] = strtod(argv[3 + 3 * i], NULL);
        t[i] = strtod(argv[4 + 3 * i], NULL);
    }
    if (greybox_law_mu(law, n, p, v, t, mu) != GREYBOX_OK) return 1;
    for (size_t i = 0; i < n; i++) printf("mu %a\n", mu[i]);
    if (greybox_law_mu_grad(law, n, p, v, t, mu, dp, dv, dt) != GREYBOX_OK) return 1;
    for (size_t i = 0; i < n; i++) printf("grad %a %a %a %a\n", mu[i], dp[i], dv[i], dt[i]);

    /* error paths: never a crash, always a code and a message */
    int fails = 0;
    double nan_p = NAN, out = 42.0;
    if (greybox_law_mu(law, 1, &nan_p, v, t, &out) != GREYBOX_ERR_INPUT || out != 42.0) fails++;
    char msg[256];
    size_t len = greybox_last_error(msg, sizeof msg);
    if (len == 0 || strstr(msg, "pressure[0]") == NULL) fails++;
    double neg = -1.0;
    if (greybox_law_mu(law, 1, &neg, v, t, &out) != GREYBOX_ERR_INPUT) fails++;
    if (greybox_law_mu(NULL, 1, p, v, t, &out) != GREYBOX_ERR_NULL) fails++;
    if (greybox_law_mu(law, 1, NULL, v, t, &out) != GREYBOX_ERR_NULL) fails++;
    if (greybox_law_mu(law, 1, p, v, NULL, &out) != GREYBOX_OK) fails++; /* NULL temperature: room temperature */
    GreyboxLaw *bad = NULL;
    if (greybox_law_load("/nonexistent/law.json", &bad) != GREYBOX_ERR_LOAD || bad != NULL) fails++;
    greybox_last_error(msg, sizeof msg);
    if (strstr(msg, "/nonexistent/law.json") == NULL) fails++;
    if (greybox_law_load(NULL, &bad) != GREYBOX_ERR_NULL) fails++;
    greybox_law_free(NULL);
    printf("version %s\n", greybox_version());
    printf("error-checks-failed %d\n", fails);
    greybox_law_free(law);
    free(p); free(v); free(t); free(mu); free(dp); free(dv); free(dt);
    return fails == 0 ? 0 : 1;
}
