/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: what one step's kernels leave for the host, read in one copy.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_REPORT_H
#define LMP_GRIDDEM_KK_REPORT_H

#include "griddem_kk_scan.h"

namespace LAMMPS_NS {

/* what the law's kernel sums: global virial and fix griddem's statistics */
struct GriddemKKSweepValue {
  double v[6];
  double energy;     // elastic energy in the springs (a pair counts half on each side)
  long contacts;     // contacts of owned atoms (an owned pair counts twice)
  int most;          // most contacts of one owned atom
};

/* why a step is computed again (GriddemKKStepReport::retry) */
enum {
  GRIDDEM_KK_RETRY_GRID = 1,     // an atom binned more than a cell outside the planned grid
  GRIDDEM_KK_RETRY_LISTS = 2,    // the contact lists outgrew their room
  GRIDDEM_KK_RETRY_ROWS = 4      // the history rows outgrew the other pool
};

/* What one step's kernels leave for the host, read in one copy after the sweep. */
struct GriddemKKStepReport {
  GriddemKKScanValue scan;
  double class_boxes[griddem_kk_class_values * GRIDDEM_MAX_CLASSES];    // GriddemKKClassScan's
  long coincident;    // the first pair of coincident centres (local indices i << 32 | j), or
                      // LONG_MAX: none
  GriddemKKSweepValue sums;
  long listed;    // list entries taken: the layout's, then those of lists that outgrew it
  long rows;      // history entries of the step's rows
  int retry;      // GRIDDEM_KK_RETRY_* bits: the sweep did nothing
};

/* the boxes of a report's scan: the whole box for one class, else the class scan's */
inline GriddemKKClassBoxes griddem_kk_boxes(const GriddemKKStepReport &report, int ncls, int nall)
{
  GriddemKKClassBoxes boxes;
  if (ncls == 1) {
    boxes.count[0] = nall;
    for (int d = 0; d < 3; d++) boxes.lo[0][d] = report.scan.lo[d], boxes.hi[0][d] = report.scan.hi[d];
    return boxes;
  }
  for (int c = 0; c < ncls; c++) {
    const double *box = report.class_boxes + griddem_kk_class_values * c;
    boxes.count[c] = (int) box[0];
    for (int d = 0; d < 3; d++) boxes.lo[c][d] = box[1 + d], boxes.hi[c][d] = box[4 + d];
  }
  return boxes;
}

}    // namespace LAMMPS_NS

#endif
