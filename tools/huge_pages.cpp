// The program's operator new asks Linux for transparent huge pages on large buffers.
//
// A large floor's segmentation and match data fill fresh full-map buffers (masks, labels,
// rasters) one after another; with 4 KB pages each page is a fault, and under a hypervisor a
// costly one: on the 240 x 160 m generated floor a third of `areamatch match`'s time was page
// faults and the zeroing they bring. Where the kernel gives huge pages only on request
// (/sys/kernel/mm/transparent_hugepage/enabled = madvise, as on the machine measured), the 2 MB-aligned
// middle of every allocation of at least a huge page (2 MB) is marked MADV_HUGEPAGE before it is
// touched. Answers do not change; only how memory is mapped. docs/performance.md has the
// measurements, and how a program of one's own gets the same (glibc's `glibc.malloc.hugetlb=1`).
//
// It also fixes glibc's mmap threshold at 4 MB (`large_block_bytes`): every block that large is
// mapped on its own and given back when freed. By default glibc raises the threshold to the
// largest block freed so far (up to 32 MB), after which a large floor's full-size buffers come
// from the heap, and, freed, leave holes there that the next stage's buffers do not fit: on the
// 240 x 160 m floor 70-100 MB of free heap stayed resident through the match. Fixing it also
// fixes the heap's trim threshold, at glibc's 128 KB unless set: the top of the heap was then
// given back and faulted in again so often that the shared pairs ran 16 % slower, so up to
// `kept_top_bytes` (16 MB) of free top is kept.
//
// The library does not do this: which pages a process wants is the program's choice.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define AREAMATCH_CLI_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define AREAMATCH_CLI_SANITIZED 1
#endif

// Under the sanitizers their own operator new stays (it checks new/delete pairs).
#if defined(__linux__) && !defined(AREAMATCH_CLI_SANITIZED)
#include <sys/mman.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#ifdef MADV_HUGEPAGE
namespace {

constexpr std::uintptr_t huge_page_bytes = std::uintptr_t{2} << 20;
constexpr int large_block_bytes = 4 << 20;
constexpr int kept_top_bytes = 16 << 20;

#if defined(__GLIBC__)
// Set before main runs; a block allocated earlier is freed the way it was made either way.
[[maybe_unused]] const bool malloc_thresholds_set =
    mallopt(M_MMAP_THRESHOLD, large_block_bytes) == 1 && mallopt(M_TRIM_THRESHOLD, kept_top_bytes) == 1;
#endif

void* allocate(std::size_t bytes) {
  if (bytes == 0) bytes = 1;
  void* p = std::malloc(bytes);
  while (p == nullptr) {  // as the standard operator new: the new-handler, else bad_alloc
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
    p = std::malloc(bytes);
  }
  if (bytes >= huge_page_bytes) {
    const auto start = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t begin = (start + huge_page_bytes - 1) & ~(huge_page_bytes - 1);
    const std::uintptr_t end = (start + bytes) & ~(huge_page_bytes - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
  }
  return p;
}

void* allocate_nothrow(std::size_t bytes) noexcept {
  try {
    return allocate(bytes);
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

void* operator new(std::size_t bytes) { return allocate(bytes); }
void* operator new[](std::size_t bytes) { return allocate(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept { return allocate_nothrow(bytes); }
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept { return allocate_nothrow(bytes); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

#endif  // MADV_HUGEPAGE
#endif  // __linux__ && not sanitized
