/* Nanoseconds per MPFR operation at a given precision, for the GMP/MPFR it is linked with.
 * Used by scripts/gmp_system.sh to compare the libraries rug compiles (gmp-mpfr-sys) with
 * Debian's libgmp-dev/libmpfr-dev. Operands are fixed non-trivial values; each operation runs in a
 * loop (calls into the library, which the compiler cannot remove). Prints one line per operation:
 * NAME NS_PER_OP (best of 5 rounds, CPU time). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <gmp.h>
#include <mpfr.h>

static double cpu_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

enum { MUL, ADD, FMA, DIV, SQRT, SIN_COS, EXP, LOG, N_OPS };
static const char *NAMES[N_OPS] = {"mul", "add", "fma", "div", "sqrt", "sin_cos", "exp", "log"};

int main(int argc, char **argv) {
  long bits = argc > 1 ? atol(argv[1]) : 336;
  long loops = argc > 2 ? atol(argv[2]) : 200000;
  mpfr_t x, y, z, r, s;
  mpfr_inits2(bits, x, y, z, r, s, (mpfr_ptr)0);
  /* x = 1/3, y = sqrt 2, z = pi/7: every bit of the mantissas in use. */
  mpfr_set_ui(x, 1, MPFR_RNDN);
  mpfr_div_ui(x, x, 3, MPFR_RNDN);
  mpfr_sqrt_ui(y, 2, MPFR_RNDN);
  mpfr_const_pi(z, MPFR_RNDN);
  mpfr_div_ui(z, z, 7, MPFR_RNDN);
  printf("# gmp %s, mpfr %s, %ld bits\n", gmp_version, mpfr_get_version(), bits);
  for (int op = 0; op < N_OPS; op++) {
    long n = op >= SIN_COS ? loops / 10 : loops;
    double best = 1e300;
    for (int round = 0; round < 5; round++) {
      double t0 = cpu_now();
      for (long i = 0; i < n; i++) {
        switch (op) {
        case MUL: mpfr_mul(r, x, y, MPFR_RNDN); break;
        case ADD: mpfr_add(r, x, z, MPFR_RNDN); break;
        case FMA: mpfr_fma(r, x, y, z, MPFR_RNDN); break;
        case DIV: mpfr_div(r, x, y, MPFR_RNDN); break;
        case SQRT: mpfr_sqrt(r, y, MPFR_RNDN); break;
        case SIN_COS: mpfr_sin_cos(r, s, x, MPFR_RNDN); break;
        case EXP: mpfr_exp(r, z, MPFR_RNDN); break;
        case LOG: mpfr_log(r, y, MPFR_RNDN); break;
        }
      }
      double dt = cpu_now() - t0;
      if (dt < best) best = dt;
    }
    printf("%s %.1f\n", NAMES[op], 1e9 * best / n);
  }
  mpfr_clears(x, y, z, r, s, (mpfr_ptr)0);
  return 0;
}
