// MPI's C header, for the files built with FRETBEM_MPI: the C API only (Open MPI's and
// MPICH's deprecated C++ bindings need their own library). Internal to src/.
#pragma once

#ifdef FRETBEM_MPI
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif
