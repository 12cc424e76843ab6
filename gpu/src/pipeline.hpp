// SPDX-License-Identifier: MIT
// The CUDA pipeline (SPEC §2–§4), written once over the execution layer (exec/exec.hpp) and
// compiled twice: by nvcc for the device (CudaExec: cuda_pipeline.cu, Backend::Cuda) and by g++
// for the host backend (HostExec: host_pipeline.cpp, Backend::CudaHost). The CPU pipeline's
// stages (cpu/src/cpu_pipeline.cpp), one kernel per stage.
//
// The files, by stage (this header includes them all; cuda_pipeline.cu and host_pipeline.cpp
// include it):
// - pipeline_class.hpp: the class CudaPipeline<Exec>: its state, load(), step() and the batch
//   (stepBatch()), the launches of the step;
// - pipeline_rebuild.hpp: its rebuild (lists, reordering, the histories across it);
// - pipeline_readout.hpp: its read-outs, the hooks of a domain decomposition, findPairs();
// - the functors they launch: pipeline_step_fns.hpp (the step and the batch's skin test),
//   pipeline_list_fns.hpp (the candidate and mesh rows, the histories), pipeline_reorder_fns.hpp
//   (the reordering), pipeline_readout_fns.hpp (the read-outs and the hooks).
//
// Design notes
// - Same functions, same bits. Every per-element decision or force is a shared TUMBLE_HD
//   function of core/ (kernels/step.hpp, kernels/contact_list.hpp), called with the same
//   arguments as on the CPU; with --fmad=false (TUMBLE_STRICT_FP) the state is bit-identical to
//   the CPU pipeline's after every step. Both pipelines step a body in one pass (stepBody(): its
//   particles' forces summed in order as they come, then its integration), one thread per body
//   here: a body's force and torque stay in registers, no per-particle force is stored and read
//   back (the lever DEM-Engine measured for clumps), and the sums are the CPU's in its order.
// - Contacts as state. The candidate list is rebuilt only when the skin test asks (the drift
//   since the last rebuild: a max and a box of displacements, by integer atomics on
//   order-preserving images of the floats, exact in any order); the rows are sorted by scene
//   index, so the contacts and their order do not depend on the sweep's output order, the skin or
//   the internal numbering.
// - Determinism of the run itself: every output element has one writer, scans are integer scans,
//   sorts are stable, and the only atomics are an integer max/min and an integer count.
// - Host synchronisation: none between the steps of a batch (up to kMaxBatch = 64 steps of one
//   step() call): each step's skin test runs on the device (DecideFn) and, where it asks for a
//   rebuild, the batch's later steps do nothing; the host reads the batch's outcome (the steps
//   taken, their read-backs) once at its end and rebuilds before the next step. A batch lasts
//   about as long as the list did before (m_batch), so that few skipped steps are launched. With
//   moving walls, their walls and mesh poses for every step of the batch are computed on the
//   host and copied in one copy before it; each step's view points at its own. At a rebuild: the
//   broadphase's read-backs (bounds, record and entry totals), the lists' totals and the kept
//   histories' total.
// - Host memory handed to a copy stays as it is until the stream has reached the copy (members,
//   or locals that outlive a synchronize()): the host backend checks it (host_exec.hpp).
#pragma once
#include "pipeline_class.hpp"
#include "pipeline_readout.hpp"
#include "pipeline_rebuild.hpp"
