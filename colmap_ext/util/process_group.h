// The processes of one run (issue 19): the ranks of an MPI job when the
// executable was started by an MPI launcher (mpirun / mpiexec of OpenMPI,
// or a cluster's srun with PMI / PMIx), else this process alone. The
// per-image commands (line_extractor, lidar_patch_match_stereo) split their
// images over the ranks of a workspace on a shared filesystem; rank 0 owns
// the database. Started without a launcher, nothing of MPI is initialised
// (a plain run never depends on the MPI runtime's state).
//
// Only the main thread calls MPI (MPI_THREAD_FUNNELED): the commands' worker
// threads compute, the main thread meets the other ranks.
// Every collective below must be reached by all ranks in the same order;
// the per-image loops therefore catch their errors and meet at CheckAllOk
// before anyone throws, so that one rank's bad image ends the whole job
// with its message instead of leaving the others waiting.
#pragma once

#include <cstddef>
#include <exception>
#include <string>
#include <vector>

namespace colmap_lidar {

class ProcessGroup {
 public:
  // The group of this process. The first call initialises MPI when a
  // launcher started the process (OMPI_COMM_WORLD_SIZE, PMI_SIZE or
  // PMIX_RANK in the environment) and registers its finalisation at exit.
  static const ProcessGroup& World();

  int Rank() const { return rank_; }
  int Size() const { return size_; }
  bool IsRoot() const { return rank_ == 0; }
  // More than one rank.
  bool Distributed() const { return size_ > 1; }
  // Item `index` of a list that every rank walks in the same order belongs
  // to this rank (round robin: neighbouring images, which cost about the
  // same, go to different ranks).
  bool Owns(size_t index) const {
    return static_cast<int>(index % static_cast<size_t>(size_)) == rank_;
  }

  // Collective: waits for every rank, then rethrows `error` on the rank
  // that had it, and on the others throws an Error with the message of the
  // lowest failed rank (so that whichever rank's message the launcher
  // shows before it stops the job names the file at fault). Does nothing
  // when no rank failed. `what` names the step.
  void CheckAllOk(const std::exception_ptr& error,
                  const std::string& what) const;

  // Collective: element-wise sums over the ranks, the result on every rank.
  std::vector<double> Sum(const std::vector<double>& values) const;

  // Collective: rank 0's `bytes` replace every other rank's.
  void Broadcast(std::string* bytes) const;

  // Collective: on rank 0, every rank's `bytes` by rank (its own first);
  // empty on the other ranks.
  std::vector<std::string> GatherToRoot(const std::string& bytes) const;

 private:
  ProcessGroup() = default;

  int rank_ = 0;
  int size_ = 1;
};

}  // namespace colmap_lidar
