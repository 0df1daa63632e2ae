// Scalar, ordinal and node types shared by every part of impm.
#pragma once

#include <Kokkos_Core.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Export.hpp>

// A cold path kept out of line, so that the hot code around it keeps its values in registers.
#if defined(__GNUC__)
#define IMPM_NOINLINE __attribute__((noinline))
#else
#define IMPM_NOINLINE
#endif

namespace impm {

using Scalar = double;
using LO = int;
using GO = long long;
// The one node type this Trilinos instantiates (OpenMP when built by cmake/setup-deps.sh).
using Node = Tpetra::Map<LO, GO>::node_type;
using ExecutionSpace = Node::execution_space;
using MemorySpace = Node::memory_space;
using DeviceType = Kokkos::Device<ExecutionSpace, MemorySpace>;

using Map = Tpetra::Map<LO, GO, Node>;
using Vector = Tpetra::Vector<Scalar, LO, GO, Node>;
using MultiVector = Tpetra::MultiVector<Scalar, LO, GO, Node>;
using Import = Tpetra::Import<LO, GO, Node>;
using Export = Tpetra::Export<LO, GO, Node>;

}  // namespace impm
