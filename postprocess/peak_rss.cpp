// postprocess/peak_rss.cpp -- peak_rss FILE CMD [ARG...]: runs CMD and writes to FILE its peak resident size
// in KiB (wait4's ru_maxrss: CMD and every descendant it reaped, the largest single process), then ends as CMD
// ended: its exit status, or killed by the same signal.
//
// Why a launcher: Linux starts a child's peak from its parent's resident size (the copy of the parent that
// fork makes is resident until exec, and exec records its size), so a run forked straight from a bench of
// 60 to 300 MiB of Python read at least that much whatever it used. Forked from this process (under 2 MiB),
// a run's peak is its own. postprocess/driver.py starts every timed run through it; `make deps` builds it.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: peak_rss FILE CMD [ARG...]\n");
        return 2;
    }
    // CMD starts with no signal blocked whatever its caller held back (Popen's child keeps its parent's mask),
    // and this process can end by CMD's signal
    sigset_t none_blocked;
    sigemptyset(&none_blocked);
    sigprocmask(SIG_SETMASK, &none_blocked, nullptr);
    pid_t child = fork();
    if (child < 0) {
        std::fprintf(stderr, "peak_rss: fork failed: %s\n", std::strerror(errno));
        return 127;
    }
    if (child == 0) {
        execvp(argv[2], argv + 2);
        std::fprintf(stderr, "peak_rss: cannot run %s: %s\n", argv[2], std::strerror(errno));
        _exit(127);
    }
    // SIGINT and SIGTERM reach CMD through its process group (jobs.py); this process outlives it to report
    signal(SIGINT, SIG_IGN);
    signal(SIGTERM, SIG_IGN);
    int status = 0;
    struct rusage usage;
    while (wait4(child, &status, 0, &usage) < 0)
        if (errno != EINTR) {
            std::fprintf(stderr, "peak_rss: wait4 failed: %s\n", std::strerror(errno));
            return 127;
        }
    FILE *f = std::fopen(argv[1], "w");
    if (!f || std::fprintf(f, "%ld\n", usage.ru_maxrss) < 0 || std::fclose(f) != 0) {
        std::fprintf(stderr, "peak_rss: cannot write %s: %s\n", argv[1], std::strerror(errno));
        return 127;
    }
    if (WIFSIGNALED(status)) {                 // end as CMD did, without a core file of this process
        struct rlimit none = {0, 0};
        setrlimit(RLIMIT_CORE, &none);
        signal(WTERMSIG(status), SIG_DFL);
        raise(WTERMSIG(status));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 127;
}
