/* GRIDDEM reduced-order model file (fix griddem/rom; format versions 1 to 3, see
 * doc/fix_griddem_rom.md): '#' starts a comment; then
 *   griddem/rom VERSION
 *   grid NX NY NZ
 *   box XLO XHI YLO YHI ZLO ZHI
 *   frame moving             (version 2, optional: the box is relative to the fix's origin)
 *   controls NC
 *   lambda L
 *   form linear|occupancy    (version 3, optional: default linear)
 *   weights NROW NCOL        (NROW = 3 NX NY NZ; NCOL = 1 + NX NY NZ + NC, occupancy 1 + NC)
 * and NROW x NCOL numbers: row 3 m + d gives velocity component d of voxel m = i + NX (j + NY k)
 * as bias + sum_m' w density(m') + sum_c w control(c) (occupancy: density(m) (bias + sum_c w
 * control(c))); then optionally (version 2)
 *   force 3 NCOL
 * and 3 x NCOL numbers, the force on a tool (x, y, z) from the same features as a row of weights
 * (occupancy: bias + sum_c w control(c), no density); then the end of the file. Every mismatch
 * is an error that names it, its line and what was expected there. */
#ifndef GRIDDEM_ROM_MODEL_H
#define GRIDDEM_ROM_MODEL_H

#include "griddem_rom.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct griddem_rom_model {
  int version;
  griddem_rom_grid box;    /* the voxels of the file's box (periodic: 0, the caller's to set) */
  int moving;              /* line 'frame moving' */
  int ncontrol;
  double lambda;           /* the ridge parameter of the training (recorded, not used) */
  int form;                /* enum griddem_rom_form */
  double *weights;         /* [3 nvoxel][1 + nvoxel + ncontrol], occupancy [3 nvoxel][1 + ncontrol] */
  double *force;           /* block 'force': [3][NCOL of weights], or NULL without it */
} griddem_rom_model;

/* A message buffer of this many bytes plus the file name's length holds every message whole
 * (a longer one is cut short). */
#define GRIDDEM_ROM_MODEL_MESSAGE 1024

/* Reads the model file at path into *model. Returns 0, or -1 with the reason in message
 * (message_size bytes, NUL-terminated) and *model empty. Free a model with
 * griddem_rom_model_free. */
int griddem_rom_model_read(const char *path, griddem_rom_model *model, char *message,
                           size_t message_size);

/* The same for a model file's text of len bytes (any bytes) named name in messages. */
int griddem_rom_model_parse(const char *name, const char *text, size_t len,
                            griddem_rom_model *model, char *message, size_t message_size);

void griddem_rom_model_free(griddem_rom_model *model);

#ifdef __cplusplus
}
#endif
#endif
