/* Eight threads evaluate one law at once; each compares with the single-threaded result. */
#include <pthread.h>
#include <stdio.h>
#include "greybox.h"

#define N 4096
#define THREADS 8
static GreyboxLaw *law;
static double p[N], v[N], t[N], reference[N];

static void *work(void *arg) {
    long id = (long)arg;
    double mu[N];
    for (int round = 0; round < 50; round++) {
        if (greybox_law_mu(law, N, p, v, t, mu) != GREYBOX_OK) return (void *)1;
        for (int i = 0; i < N; i++)
            if (mu[i] != reference[i]) return (void *)2;
    }
    (void)id;
    return NULL;
}

int main(int argc, char **argv) {
    if (argc != 2 || greybox_law_load(argv[1], &law) != GREYBOX_OK) return 2;
    for (int i = 0; i < N; i++) {
        p[i] = 9.0e8 + 1.3e9 * (double)(i % 97) / 96.0;
        v[i] = 0.3 + 3.9 * (double)(i % 89) / 88.0;
        t[i] = 293.15;
    }
    if (greybox_law_mu(law, N, p, v, t, reference) != GREYBOX_OK) return 2;
    pthread_t th[THREADS];
    for (long k = 0; k < THREADS; k++) pthread_create(&th[k], NULL, work, (void *)k);
    int bad = 0;
    for (int k = 0; k < THREADS; k++) {
        void *r;
        pthread_join(th[k], &r);
        if (r != NULL) bad++;
    }
    greybox_law_free(law);
    printf("threads %d bad %d\n", THREADS, bad);
    return bad == 0 ? 0 : 1;
}
