// How much memory a rank's node gives the job: the physical memory, or less where the job runs
// under a memory limit. Batch systems enforce theirs with cgroups (SLURM's --mem and
// --mem-per-cpu, PBS's mem, a container's limit), which sysconf's page count does not see: a
// bound taken from the node's physical memory lets a run grow until the job is killed.
#pragma once

#include <filesystem>
#include <string>

namespace radiosity::run {

/// Bytes of memory this process may use on its node: min(physical memory, the limit of its
/// cgroup and of every cgroup above it), as read from /proc/self/cgroup and /sys/fs/cgroup.
double nodeMemoryBytes();

/// The tightest memory limit on the cgroup that `procSelfCgroup` (the text of
/// /proc/self/cgroup) names, and on its ancestors, read under `cgroupRoot` (/sys/fs/cgroup):
/// cgroup v2's memory.max (the line "0::/path") or v1's memory.limit_in_bytes (the line whose
/// controllers include memory, under cgroupRoot/memory). Where the named cgroup is not there (a
/// cgroup namespace, whose root is the process's own cgroup), the controller's root is read. 0
/// when no limit is set ("max", or v1's near-2^63 "unlimited") or none can be read.
double cgroupMemoryLimit(const std::string& procSelfCgroup,
                         const std::filesystem::path& cgroupRoot);

}  // namespace radiosity::run
