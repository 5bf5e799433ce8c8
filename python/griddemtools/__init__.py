"""GRIDDEM's Python tools for the examples' and the benchmarks' scripts: readers of LAMMPS's text
outputs and the way those scripts start LAMMPS. Standard library only, but for plot (matplotlib)
and rom (numpy), which only the scripts that draw or fit import.

  items     the ITEM headers of a text dump and the lines under each (dump and grid read them)
  dump      atom dumps (dump custom, atom): snapshots of per-atom columns; two dumps' largest
            relative difference
  grid      dump grid text files: per-cell columns of each frame
  chunks    fix ave/chunk files: the blocks of per-chunk rows
  log       a log or screen output: thermo columns, loop times, timing breakdown, reference logs
  echo      whether a log echoes an input script, command by command
  lammps    the lmp to run (GRIDDEM_LMP or build/lmp) and how: mpirun, threads, root's Open MPI;
            where the sub-model table's printer is
  spheres   data files of random polydisperse spheres (the tests' scenes, bench/tradeoff.py)
  analytic  the analytic references of the NN4DEM single-particle scenes
  plot      drawing helpers shared by the examples' figures (matplotlib)
  squeeze   the 1:4 bidisperse squeeze's packing and input (a test's and the benchmarks' scene)
  rom       fix griddem/rom's model files, the ridge fits of a model, and what a reduced run is
            measured by (fill heights, kinematic shares): examples/rom-*, bench/rom.py (numpy)
  blade     examples/rom-blade's measures: snapshots binned in the blade's frame, the force on
            the blade and its accuracy (numpy)

A script finds the package by one line that puts this repository's python/ folder first on its
path, relative to the script's own file (examples/NAME/x.py: "..", "..", "python"; bench/x.py:
"..", "python"):

    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
"""
