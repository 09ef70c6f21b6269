// tests/fault/fail_write.cpp — an LD_PRELOAD shim that makes write(2) to regular files fail
// with ENOSPC once FORTU_FAIL_WRITE_AFTER bytes have gone to them: a full disk without a
// mount, for the writers' tests. Terminals, pipes and sockets are left alone. fwrite(3) is
// failed too (glibc's stdio calls its own write, which LD_PRELOAD cannot reach), as a full
// disk fails it for libraries writing through stdio; and writev(2), which libstdc++'s file
// streams use (OpenEXR's multi-part files).
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long long written;

// The bytes still allowed to `fd`, or -1 when it is not a regular file (or no limit is set).
static long long room(int fd) {
    const char* limit = getenv("FORTU_FAIL_WRITE_AFTER");
    struct stat st;
    if (!limit || fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return -1;
    const long long left = atoll(limit) - written;
    return left < 0 ? 0 : left;
}

extern "C" ssize_t write(int fd, const void* data, size_t size) {
    static auto real_write = reinterpret_cast<ssize_t (*)(int, const void*, size_t)>(dlsym(RTLD_NEXT, "write"));
    const long long left = room(fd);
    if (left < 0) return real_write(fd, data, size);
    if (size > 0 && left == 0) {
        errno = ENOSPC;
        return -1;
    }
    const ssize_t done = real_write(fd, data, left < static_cast<long long>(size) ? static_cast<size_t>(left) : size);
    if (done > 0) written += done;
    return done;
}

// libstdc++'s file streams (OpenEXR's) write through writev(2): refused whole past the limit.
extern "C" ssize_t writev(int fd, const struct iovec* pieces, int count) {
    static auto real_writev = reinterpret_cast<ssize_t (*)(int, const struct iovec*, int)>(dlsym(RTLD_NEXT, "writev"));
    const long long left = room(fd);
    if (left < 0) return real_writev(fd, pieces, count);
    long long size = 0;
    for (int i = 0; i < count; ++i) size += static_cast<long long>(pieces[i].iov_len);
    if (size > left) {
        errno = ENOSPC;
        return -1;
    }
    const ssize_t done = real_writev(fd, pieces, count);
    if (done > 0) written += done;
    return done;
}

extern "C" size_t fwrite(const void* data, size_t item, size_t count, FILE* stream) {
    static auto real_fwrite =
        reinterpret_cast<size_t (*)(const void*, size_t, size_t, FILE*)>(dlsym(RTLD_NEXT, "fwrite"));
    const long long left = item == 0 ? -1 : room(fileno(stream));
    if (left < 0) return real_fwrite(data, item, count, stream);
    const size_t items = static_cast<unsigned long long>(left) / item < count ? static_cast<size_t>(left) / item : count;
    const size_t done = real_fwrite(data, item, items, stream);
    written += static_cast<long long>(done * item);
    if (done < count) errno = ENOSPC;
    return done;
}
