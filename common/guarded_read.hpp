#pragma once
// A read that may crash or hang inside a library, tried first in a child process.
//
// libhdf5 1.10.8 (Debian's) dereferences corrupted object headers without checking them: a
// damaged attribute table crashes H5Aiterate2 (SIGSEGV in H5A__close), a damaged contiguous
// layout makes H5D__contig_read memcpy out of bounds, a damaged global-heap entry loops forever
// in H5HG__protect (fuzz/README.md, fuzz/known-libhdf5/). None of this can be caught in the
// process that suffers it. guarded_read runs the read in a forked child first: the child's
// crash or hang becomes an InputError naming the file, and only a file the child read to the end
// is read again in this process (double reading costs one extra read of the file; a 100 MB mesh
// reads in about a second).
#include <filesystem>
#include <functional>
#include <string>

namespace adamss {

/// Seconds a guarded read may take before it counts as hung: ADAMSS_HDF5_GUARD_SECONDS if set
/// (> 0), else 60 s plus 1 s per 10 MB of `file`.
[[nodiscard]] double guard_seconds(const std::filesystem::path& file);

/// Memory a guarded read may add to the process, MB (2^20 bytes): ADAMSS_HDF5_GUARD_MB if set
/// (> 0), else 2048 MB plus 64 MB per MB of `file` (a mesh file holds its arrays at most
/// deflate-compressed; 64x leaves room for the reader's own copies). The child's address space is
/// capped at the parent's size plus this (RLIMIT_AS): libhdf5 1.10 mallocs sizes read from
/// corrupted headers (4 GB for a 50 kB file, fuzz/known-libhdf5/hdf5-4gb-allocation.h5); capped,
/// the allocation fails in the child and the file is never read in the process.
[[nodiscard]] double guard_megabytes(const std::filesystem::path& file);

/// Runs `read` in a forked child process (fork, then `read`, then _exit). Returns normally when
/// the child finished `read` without a crash or an exception; the caller then does the real read.
/// InputError naming `file`:
///  - with the child's message when `read` threw an InputError there (the same error the real
///    read would give);
///  - when the child died from a signal ("the HDF5 library crashed (SIGSEGV) reading it: the file
///    is corrupted"), or ran over guard_seconds(file) (then it is killed);
///  - when `read` threw std::bad_alloc in the child, whose address space is capped at
///    guard_megabytes(file) beyond the parent's ("needed more than N MB").
/// In an AddressSanitizer build, a report in the child whose first frames lie in the library
/// ("lib" + `what` in lower case: libhdf5) is an InputError as well ("made an invalid memory
/// access reading it"): libhdf5 1.10 over-reads heap buffers on some corrupted headers, which
/// goes unnoticed without ASan.
/// Another exception in the child, or another exit code (a sanitizer's
/// report on our own code: the child resets SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT to their
/// defaults, so only such a report exits without a signal), returns normally: the real read
/// throws or reports it again in this process. `what` names the library in the messages ("HDF5"). With
/// ADAMSS_HDF5_GUARD=0 in the environment nothing is forked and the call returns at once; also
/// when fork itself fails (no memory, process limit): the read is then unguarded.
void guarded_read(const std::filesystem::path& file, const std::string& what, const std::function<void()>& read);

}  // namespace adamss
