/* The reduced-order model file: a version 1, a version 2 (comments, a moving frame, a force
 * block) and two version 3 texts (form occupancy, and linear by default) read back number for number; each malformed text refused with the message that
 * names its line and what was expected there (those of unittest/lammps/test_rom.py among them);
 * bytes other than printable ASCII shown as \xNN, at most 40 of them; numbers in messages as
 * LAMMPS's fmt writes them ("{}"); a file that is missing. */
#include "check.h"
#include "griddem_rom_model.h"

#include <stdlib.h>
#include <string.h>

#define NAME "m.model"

/* a 2 x 1 x 1 grid, 1 control: weights 6 x 4; the value of row r, column c is r + c / 8 */
static const char *const HEAD1 =
    "# a model\n"
    "griddem/rom 1\n"
    "grid 2 1 1\n"
    "box 0 4 0 1 -1 1   # comment after values\n"
    "controls 1\n"
    "lambda 0.5\n"
    "weights 6 4\n";

static char *weights_text(int nrow, int ncol)
{
  char *text = malloc(32 * (size_t) nrow * ncol + 1), *o = text;
  for (int r = 0; r < nrow; r++) {
    for (int c = 0; c < ncol; c++) o += sprintf(o, c ? " %g" : "%g", r + c / 8.0);
    *o++ = '\n';
  }
  *o = '\0';
  return text;
}

/* text with the first occurrence of from replaced by to */
static char *replaced(const char *text, const char *from, const char *to)
{
  const char *at = strstr(text, from);
  char *out = malloc(strlen(text) + strlen(to) + 1);
  memcpy(out, text, (size_t) (at - text));
  strcpy(out + (at - text), to);
  strcat(out, at + strlen(from));
  return out;
}

/* head + 6 rows of ncol weights + tail as one text */
static char *model_text_columns(const char *head, int ncol, const char *tail)
{
  char *w = weights_text(6, ncol);
  char *text = malloc(strlen(head) + strlen(w) + strlen(tail) + 1);
  strcat(strcat(strcpy(text, head), w), tail);
  free(w);
  return text;
}

/* head + the 6 x 4 weights of HEAD1 + tail as one text */
static char *model_text(const char *head, const char *tail)
{
  return model_text_columns(head, 4, tail);
}

/* a version 3 model of form occupancy: the grid and control of HEAD1, 6 x 2 weights, then tail */
static char *occupancy_text(const char *tail)
{
  char *v3 = replaced(HEAD1, "griddem/rom 1", "griddem/rom 3");
  char *head = replaced(v3, "weights 6 4", "form occupancy\nweights 6 2");
  char *text = model_text_columns(head, 2, tail);
  free(head);
  free(v3);
  return text;
}

/* the message of a text (len bytes) the parser refuses, "" if it accepts it */
static const char *refusal(const char *text, size_t len)
{
  static char message[GRIDDEM_ROM_MODEL_MESSAGE + sizeof NAME];
  griddem_rom_model model;
  if (griddem_rom_model_parse(NAME, text, len, &model, message, sizeof message) == 0) {
    griddem_rom_model_free(&model);
    return "";
  }
  CHECK(model.weights == NULL && model.force == NULL, "a refused model holds nothing");
  return message;
}

static void check_refused(const char *text, size_t len, const char *expected)
{
  const char *got = refusal(text, len);
  CHECK(strcmp(got, expected) == 0, "\n  expected: %s\n  got:      %s", expected, got);
}

#define REFUSED(text, expected) check_refused(text, strlen(text), expected)

static void check_good(void)
{
  char *text = model_text(HEAD1, "");
  griddem_rom_model m;
  char message[GRIDDEM_ROM_MODEL_MESSAGE + sizeof NAME] = "";
  CHECK(griddem_rom_model_parse(NAME, text, strlen(text), &m, message, sizeof message) == 0, "version 1: %s",
        message);
  CHECK(m.version == 1 && !m.moving && m.ncontrol == 1 && m.lambda == 0.5 && m.force == NULL,
        "version 1 head: version %d moving %d controls %d lambda %g", m.version, m.moving, m.ncontrol, m.lambda);
  CHECK(m.box.n[0] == 2 && m.box.n[1] == 1 && m.box.n[2] == 1 && m.box.lo[0] == 0.0 && m.box.hi[0] == 4.0 &&
            m.box.lo[2] == -1.0 && m.box.hi[2] == 1.0,
        "version 1 grid and box");
  int same = 1;
  for (int r = 0; r < 6; r++)
    for (int c = 0; c < 4; c++) same &= m.weights[4 * r + c] == r + c / 8.0;
  CHECK(same, "version 1 weights, row by row");
  griddem_rom_model_free(&m);
  free(text);

  char *v2 = replaced(HEAD1, "griddem/rom 1", "griddem/rom 2");
  char *head2 = replaced(v2, "controls", "frame moving\ncontrols");
  free(v2);
  text = model_text(head2, "force 3 4\n1 2 3 4\n5 6 7 8\n9 10 11 1e-3\n# the end\n");
  CHECK(griddem_rom_model_parse(NAME, text, strlen(text), &m, message, sizeof message) == 0, "version 2: %s",
        message);
  CHECK(m.version == 2 && m.moving && m.force && m.force[0] == 1.0 && m.force[7] == 8.0 && m.force[11] == 1e-3 &&
            m.weights[23] == 5.375 && m.form == GRIDDEM_ROM_LINEAR,
        "version 2: moving frame, force block, weights");
  griddem_rom_model_free(&m);
  free(text);
  free(head2);

  /* version 3, form occupancy: 6 rows of 1 + 1 columns */
  text = occupancy_text("");
  CHECK(griddem_rom_model_parse(NAME, text, strlen(text), &m, message, sizeof message) == 0, "version 3: %s",
        message);
  CHECK(m.version == 3 && m.form == GRIDDEM_ROM_OCCUPANCY && m.ncontrol == 1 && m.weights[2 * 5 + 1] == 5.125,
        "version 3: form occupancy, weights");
  griddem_rom_model_free(&m);
  free(text);
  /* its force block has the weights' columns (bias, control) */
  text = occupancy_text("force 3 2\n1 2\n3 4\n5 -6\n");
  CHECK(griddem_rom_model_parse(NAME, text, strlen(text), &m, message, sizeof message) == 0 && m.force &&
            m.force[0] == 1.0 && m.force[3] == 4.0 && m.force[5] == -6.0,
        "version 3: form occupancy with a force block of 3 x 2 (%s)", message);
  griddem_rom_model_free(&m);
  free(text);
  /* version 3 without a form line: linear */
  char *v3 = replaced(HEAD1, "griddem/rom 1", "griddem/rom 3");
  text = model_text(v3, "");
  CHECK(griddem_rom_model_parse(NAME, text, strlen(text), &m, message, sizeof message) == 0 &&
            m.form == GRIDDEM_ROM_LINEAR && m.weights[23] == 5.375,
        "version 3 without form: linear (%s)", message);
  griddem_rom_model_free(&m);
  free(text);
  free(v3);
}

static void check_messages(void)
{
  char *good = model_text(HEAD1, "");
  char *v2 = replaced(good, "griddem/rom 1", "griddem/rom 2");
  char *t;
  REFUSED("", "model file m.model holds no words: expected 'griddem/rom VERSION', found the end of the file");
  REFUSED("# only\n  # comments\n",
          "model file m.model holds no words: expected 'griddem/rom VERSION', found the end of the file");
  REFUSED("griddem/rom\n", "model file m.model, line 1: 'griddem/rom' needs 1 values (VERSION), found the end of the file");
  REFUSED("griddem/rom 4\n", "model file m.model, line 1: format version 4 is not supported (this build reads "
                             "versions 1 to 3)");
  REFUSED("griddem/rom 2.5\n", "model file m.model, line 1: format version 2.5 is not supported (this build reads "
                               "versions 1 to 3)");
  REFUSED("\ngriddem/rom one\n", "model file m.model, line 2: expected the format version (a finite number), found 'one'");
  REFUSED("griddem/rom 1\ngrid 2 1\n", "model file m.model, line 2: 'grid' needs 3 values (NX NY NZ), found the end of "
                                       "the file");
  REFUSED("griddem/rom 1\ngrid 2 1 1\nbox 0 4 0 1 -1\n",
          "model file m.model, line 3: 'box' needs 6 values (XLO XHI YLO YHI ZLO ZHI), found the end of the file");
  /* numbers as fmt writes a double: shortest digits, fixed from 1e-4 up to 1e16 */
  REFUSED("griddem/rom 1\ngrid 2.5 100000 1e-05\n",
          "model file m.model, line 2: grid size 2.5 100000 1e-05 must be positive integers");
  REFUSED("griddem/rom 1\ngrid 0.0001 1e16 -3\n",
          "model file m.model, line 2: grid size 0.0001 1e+16 -3 must be positive integers");
  REFUSED("griddem/rom 1\ngrid 1e400 1 1\n",
          "model file m.model, line 2: expected a number of voxels (a finite number), found '1e400'");
  t = replaced(good, "box 0 4", "box 4 4");
  REFUSED(t, "model file m.model, line 4: box bounds along axis x are not increasing");
  free(t);
  t = replaced(good, "controls 1", "frame moving\ncontrols 1");
  REFUSED(t, "model file m.model, line 5: 'frame' needs format version 2 (the file has version 1)");
  free(t);
  t = replaced(v2, "controls 1", "frame still\ncontrols 1");
  REFUSED(t, "model file m.model, line 5: expected 'frame moving' (the only frame), found 'still'");
  free(t);
  t = replaced(good, "controls 1", "controls 1.5");
  REFUSED(t, "model file m.model, line 5: number of controls 1.5 is not a count");
  free(t);
  t = replaced(good, "lambda 0.5", "ridge 0.5");
  REFUSED(t, "model file m.model, line 6: expected 'lambda L', found 'ridge'");
  free(t);
  t = replaced(good, "weights 6 4", "weights 9 4");
  REFUSED(t, "model file m.model, line 7: weights has 9 rows; grid size 2 1 1 needs 3 x 2 = 6");
  free(t);
  t = replaced(good, "weights 6 4", "weights 6 3");
  REFUSED(t, "model file m.model, line 7: weights has 3 columns; grid size 2 1 1 and 1 controls need 1 + 2 + 1 = 4");
  free(t);
  /* a weights block cut short: where the file ends, and what the header asked for */
  t = replaced(good, "5 5.125 5.25 5.375\n", "");
  REFUSED(t, "model file m.model, at its end (line 12): 'weights 6 4' (line 7) needs 6 x 4 = 24 values, found 20");
  free(t);
  t = replaced(good, "2 2.125", "2 x2.125");
  REFUSED(t, "model file m.model, line 10: expected value 2 of row 3 of 'weights' (a finite number), found 'x2.125'");
  free(t);
  /* words after the last block */
  t = model_text(HEAD1, "end\n");
  REFUSED(t, "model file m.model, line 14: expected the end of the file after the 6 x 4 weights, found 'end'");
  free(t);
  t = replaced(v2, "3 3.125 3.25 3.375\n4 4.125 4.25 4.375\n5 5.125 5.25 5.375\n",
               "3 3.125 3.25 3.375\n4 4.125 4.25 4.375\n5 5.125 5.25 5.375\nend\n");
  REFUSED(t, "model file m.model, line 14: expected the end of the file or a block 'force 3 4' after the 6 x 4 "
             "weights, found 'end'");
  free(t);
  t = model_text(HEAD1, "force 3 4\n");
  REFUSED(t, "model file m.model, line 14: 'force' needs format version 2 (the file has version 1)");
  free(t);
  char *head2 = replaced(HEAD1, "griddem/rom 1", "griddem/rom 2");
  t = model_text(head2, "force 3 5\n");
  REFUSED(t, "model file m.model, line 14: force has 3 rows and 5 columns; expected 3 and 4 (as weights)");
  free(t);
  t = model_text(head2, "force 3 4\n1 2 3 4\n5 6 7 8\n9 10 11 12\n0.5\n");
  REFUSED(t, "model file m.model, line 18: expected the end of the file after the 3 x 4 force values, found '0.5'");
  free(t);
  t = model_text(head2, "force 3 4\n1 2 3 4\n");
  REFUSED(t, "model file m.model, at its end (line 15): 'force 3 4' (line 14) needs 3 x 4 = 12 values, found 4");
  free(t);
  free(head2);
  /* the form line */
  t = replaced(v2, "weights 6 4", "form occupancy\nweights 6 2");
  REFUSED(t, "model file m.model, line 7: 'form' needs format version 3 (the file has version 2)");
  free(t);
  char *v3 = replaced(good, "griddem/rom 1", "griddem/rom 3");
  t = replaced(v3, "weights 6 4", "form quadratic\nweights 6 4");
  REFUSED(t, "model file m.model, line 7: expected 'form linear' or 'form occupancy', found 'quadratic'");
  free(t);
  t = replaced(v3, "weights 6 4", "form occupancy\nweights 6 4");
  REFUSED(t, "model file m.model, line 8: weights has 4 columns; form occupancy with 1 controls needs 1 + 1 = 2");
  free(t);
  t = occupancy_text("force 3 4\n");
  REFUSED(t, "model file m.model, line 15: force has 3 rows and 4 columns; expected 3 and 2 (as weights)");
  free(t);
  free(v3);

  /* binary bytes: a word of 64 bytes without white space is shown as its first 40 (7 bytes of an
   * ELF header, 33 NUL bytes), then ... */
  char binary[70] = "\x7f" "ELF\x02\x01\x01";
  memcpy(binary + 64, "\n\x03\x00\x00\n", 5);
  check_refused(binary, 69, "model file m.model, line 1: expected 'griddem/rom VERSION', found '\\x7fELF\\x02\\x01\\x01"
                            "\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00"
                            "\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00\\x00...'");
  /* NUL and control bytes before a row of weights (line 9), and a NUL inside a number */
  const size_t at = strstr(good, "1 1.125") - good;
  char *row = malloc(strlen(good) + 4);
  memcpy(row, good, at);
  memcpy(row + at, "\x00\x01 ", 3);
  strcpy(row + at + 3, good + at);
  check_refused(row, strlen(good) + 3,
                "model file m.model, line 9: expected value 1 of row 2 of 'weights' (a finite number), found "
                "'\\x00\\x01'");
  row[at] = '1';
  row[at + 1] = '\0';
  check_refused(row, strlen(good) + 3,
                "model file m.model, line 9: expected value 1 of row 2 of 'weights' (a finite number), found "
                "'1\\x00'");
  free(row);
  free(v2);
  free(good);
}

static void check_files(void)
{
  griddem_rom_model m;
  char message[GRIDDEM_ROM_MODEL_MESSAGE + 64];
  CHECK(griddem_rom_model_read("/nonexistent/m.model", &m, message, sizeof message) != 0 &&
            strcmp(message, "cannot open model file /nonexistent/m.model") == 0,
        "a missing file: %s", message);
  char path[] = "/tmp/griddem_rom_modelXXXXXX";
  FILE *f = fdopen(mkstemp(path), "w");
  char *text = model_text(HEAD1, "");
  fputs(text, f);
  fclose(f);
  const int status = griddem_rom_model_read(path, &m, message, sizeof message);
  CHECK(status == 0 && m.weights[4 * 5 + 3] == 5.375, "a model file read back: %s", status ? message : "");
  if (status == 0) griddem_rom_model_free(&m);
  remove(path);
  free(text);
}

int main(void)
{
  check_good();
  check_messages();
  check_files();
  return check_summary();
}
