/* Pairs that must not interact (LAMMPS neigh_modify exclude type / group / molecule, and fix
 * griddem/rom's kinematic and lagging particles), and the test both the CPU sweep and the Kokkos
 * search make of a pair. */
#ifndef GRIDDEM_EXCLUSIONS_H
#define GRIDDEM_EXCLUSIONS_H

#include "griddem_portable.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct griddem_exclusions {
  const unsigned char *type_pair; /* NULL or [(ntypes+1)^2] */
  int ntypes;
  int ngroup_pairs;
  const int *group_bits;          /* [2*ngroup_pairs]: (bit1, bit2) per excluded pair of groups */
  int both_bit;                   /* pairs whose two masks both have this bit (fix griddem/rom's
                                   * kinematic particles); 0: none */
  int apart_bit;                  /* pairs where either mask has this bit: particles that can touch
                                   * nothing this step (fix griddem/rom's lagging particles, which
                                   * its reach test keeps out of every contact); 0: none */
  int nmolecule;                  /* neigh_modify exclude molecule/intra and molecule/inter */
  const int *molecule_bits;       /* [nmolecule]: the group bit of each */
  const int *molecule_intra;      /* [nmolecule]: 1: pairs of one molecule, 0: of two */
  int group_both_bits;            /* neigh_modify exclude group G G: pairs whose two masks share
                                   * one of these bits (the pairs of two groups are group_bits') */
} griddem_exclusions;

/* The exclusions by group bits alone: pairs both of whose masks hold a bit of both, or either of
 * whose masks holds a bit of apart (both: e->both_bit | e->group_both_bits, apart: e->apart_bit) */
GRIDDEM_INLINE int griddem_excluded_by_bits(int both, int apart, int ma, int mb)
{
  return (ma & mb & both) || ((ma | mb) & apart);
}

/* Whether e excludes pairs by group bits alone (no type pairs, pairs of groups or molecules) */
GRIDDEM_INLINE int griddem_exclusions_by_bits(const griddem_exclusions *e)
{
  return !e->type_pair && !e->ngroup_pairs && !e->nmolecule;
}

/* Whether particles of types ta, tb and group masks ma, mb must not interact. */
GRIDDEM_INLINE int griddem_excluded(const griddem_exclusions *e, int ta, int ma, int tb, int mb)
{
  if (griddem_excluded_by_bits(e->both_bit | e->group_both_bits, e->apart_bit, ma, mb)) return 1;
  if (e->type_pair && e->type_pair[ta * (e->ntypes + 1) + tb]) return 1;
  for (int k = 0; k < e->ngroup_pairs; k++) {
    const int b1 = e->group_bits[2 * k], b2 = e->group_bits[2 * k + 1];
    if (((ma & b1) && (mb & b2)) || ((ma & b2) && (mb & b1))) return 1;
  }
  return 0;
}

/* Whether particles of molecules a and b, of group masks ma and mb, must not interact by the
 * molecule exclusions (both in the group, and in one molecule or in two, as LAMMPS's lists). */
GRIDDEM_INLINE int griddem_excluded_molecules(const griddem_exclusions *e, int64_t a, int ma, int64_t b, int mb)
{
  for (int k = 0; k < e->nmolecule; k++)
    if ((ma & mb & e->molecule_bits[k]) && (a == b) == (e->molecule_intra[k] != 0)) return 1;
  return 0;
}

#ifdef __cplusplus
}
#endif

#endif
