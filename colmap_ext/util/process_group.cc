#include "colmap_ext/util/process_group.h"

// MPI's C interface only (the deprecated C++ bindings need their own
// library).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <climits>
#include <cstdint>
#include <cstdlib>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

bool StartedByLauncher() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr ||
         std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

void FinalizeMpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

}  // namespace

const ProcessGroup& ProcessGroup::World() {
  static const ProcessGroup* world = [] {
    auto* group = new ProcessGroup;
    if (StartedByLauncher()) {
      int initialized = 0;
      MPI_Initialized(&initialized);
      if (!initialized) {
        // Worker threads never call MPI; only the main thread does.
        int provided = 0;
        THROW_CHECK(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED,
                                    &provided) == MPI_SUCCESS,
                    "MPI_Init_thread failed (started by an MPI launcher)");
        std::atexit(FinalizeMpi);
      }
      MPI_Comm_rank(MPI_COMM_WORLD, &group->rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &group->size_);
    }
    return group;
  }();
  return *world;
}

void ProcessGroup::CheckAllOk(const std::exception_ptr& error,
                              const std::string& what) const {
  if (size_ > 1) {
    // The lowest failed rank, or size_ when none failed.
    const int mine = error ? rank_ : size_;
    int first_failed = size_;
    MPI_Allreduce(&mine, &first_failed, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first_failed < size_) {
      std::string message;
      if (rank_ == first_failed) {
        try {
          std::rethrow_exception(error);
        } catch (const std::exception& e) {
          message = e.what();
        } catch (...) {
          message = "unknown error";
        }
      }
      uint64_t size = message.size();
      MPI_Bcast(&size, 1, MPI_UINT64_T, first_failed, MPI_COMM_WORLD);
      message.resize(size);
      MPI_Bcast(message.data(), static_cast<int>(size), MPI_CHAR, first_failed,
                MPI_COMM_WORLD);
      if (!error) {
        THROW_ERROR(what << ": rank " << first_failed << " of " << size_
                         << " failed: " << message);
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

std::vector<double> ProcessGroup::Sum(const std::vector<double>& values) const {
  if (size_ == 1) return values;
  std::vector<double> sums(values.size(), 0.0);
  MPI_Allreduce(values.data(), sums.data(), static_cast<int>(values.size()),
                MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return sums;
}

void ProcessGroup::Broadcast(std::string* bytes) const {
  if (size_ == 1) return;
  uint64_t size = bytes->size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  THROW_CHECK(size <= static_cast<uint64_t>(INT_MAX),
              "Broadcast of " << size << " bytes: more than MPI's int count");
  bytes->resize(size);
  MPI_Bcast(bytes->data(), static_cast<int>(size), MPI_BYTE, 0, MPI_COMM_WORLD);
}

std::vector<std::string> ProcessGroup::GatherToRoot(
    const std::string& bytes) const {
  if (size_ == 1) return {bytes};
  // Every rank learns every size, so that all refuse a gather beyond MPI's
  // int count alike instead of leaving the others waiting.
  const uint64_t size = bytes.size();
  std::vector<uint64_t> sizes(size_);
  MPI_Allgather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T,
                MPI_COMM_WORLD);
  uint64_t total = 0;
  for (const uint64_t part : sizes) total += part;
  THROW_CHECK(total <= static_cast<uint64_t>(INT_MAX),
              "Gather of " << total << " bytes: more than MPI's int count");
  std::vector<int> counts;
  std::vector<int> offsets;
  if (IsRoot()) {
    for (const uint64_t part : sizes) {
      offsets.push_back(counts.empty() ? 0 : offsets.back() + counts.back());
      counts.push_back(static_cast<int>(part));
    }
  } else {
    sizes.clear();
  }
  std::string all(IsRoot() ? static_cast<size_t>(total) : 0, '\0');
  MPI_Gatherv(bytes.data(), static_cast<int>(size), MPI_BYTE, all.data(),
              counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
  std::vector<std::string> parts;
  for (size_t r = 0; r < sizes.size(); ++r) {
    parts.push_back(all.substr(offsets[r], sizes[r]));
  }
  return parts;
}

}  // namespace colmap_lidar
