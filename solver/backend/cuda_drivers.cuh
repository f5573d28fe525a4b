#pragma once
// Driver functions: the only way host code launches the CUDA kernels (HOOMD-blue's pattern).
// Each takes plain pointers and a stream, and checks its launch. One header and one .cu per
// concern; this one gathers them for the subdomain.
#include "backend/cuda_cell_forces.cuh"
#include "backend/cuda_cluster_lists.cuh"
#include "backend/cuda_exchange.cuh"
#include "backend/cuda_integration.cuh"
#include "backend/cuda_neighbour_lists.cuh"
#include "backend/cuda_sort.cuh"
