#include "granular_ros/tool.h"

#include <malloc.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <thread>

namespace granular_ros {

namespace {

sigset_t stopSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGHUP);
  return signals;
}

// Set by the signal thread before it removes the partial output: from then on it, not the
// work, ends the process (with 128 + the signal), however the work fares meanwhile.
std::atomic<bool> g_stopping{false};

// The work ended (done or failed): if a signal is being handled, a write that failed because
// its folder was just removed is no failure of its own; wait for the signal thread's _exit.
int unlessStopping(int status) {
  while (g_stopping.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return status;
}

// "NAME: " on a line of its own, past a progress line that a terminal leaves unfinished.
std::string messagePrefix(const std::string& name) {
  return (ProgressReport::terminal() ? "\n" : "") + name + ": ";
}

}  // namespace

void stopCleanlyOnSignals(const std::string& name) {
  const sigset_t signals = stopSignals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread([name, signals] {
    int signal_number = 0;
    while (sigwait(&signals, &signal_number) != 0) {
    }
    g_stopping.store(true);
    const bool removed = !granular::removePendingOutputs().empty();
    const std::string line = messagePrefix(name) + "interrupted by SIG" +
                             sigabbrev_np(signal_number) +
                             (removed ? "; partial output removed\n" : "\n");
    const ssize_t ignored = ::write(STDERR_FILENO, line.data(), line.size());
    (void)ignored;
    // _exit: the other threads are still running, so no destructor or atexit handler may run.
    ::_exit(128 + signal_number);
  }).detach();
}

void reuseFreedMemory() {
  constexpr int kLargestHeapBlock = 32 << 20;  // glibc's largest mmap threshold
  constexpr int kKeptFreeMemory = 256 << 20;
  mallopt(M_MMAP_THRESHOLD, kLargestHeapBlock);
  mallopt(M_TRIM_THRESHOLD, kKeptFreeMemory);
}

Tool::Tool(std::string name, std::string about, std::string epilogue)
    : name_(std::move(name)), about_(std::move(about)), epilogue_(std::move(epilogue)) {
  options_.help(help_);
}

int Tool::run(int argc, char** argv, const std::function<void()>& configure,
              const std::function<void()>& work) {
  stopCleanlyOnSignals(name_);
  reuseFreedMemory();
  try {
    options_.parse(argc, argv);
    if (help_) {
      std::cout << about_ << "\noptions:\n" << options_.help() << "\n" << epilogue_;
      return kExitDone;
    }
    configure();
  } catch (const std::exception& error) {
    std::cerr << name_ << ": " << error.what() << "\n(see " << name_ << " --help)\n";
    return kExitBadUsage;
  }
  try {
    work();
  } catch (const UsageError& error) {
    if (!g_stopping.load()) {
      std::cerr << messagePrefix(name_) << error.what() << '\n';
    }
    return unlessStopping(kExitBadUsage);
  } catch (const std::exception& error) {
    if (!g_stopping.load()) {
      std::cerr << messagePrefix(name_) << error.what() << '\n';
    }
    return unlessStopping(kExitFailed);
  }
  return unlessStopping(kExitDone);
}

std::function<void(std::size_t, std::size_t)> Tool::progress(const std::string& what,
                                                             const std::string& unit,
                                                             std::size_t lines) const {
  return [report = ProgressReport(lines), what, unit](std::size_t done, std::size_t total) mutable {
    report(what, done, total, unit);
  };
}

void Tool::warn(const std::vector<std::string>& warnings) const {
  for (const std::string& warning : warnings) {
    std::cerr << name_ << ": warning: " << warning << '\n';
  }
}

granular::OutputPolicy Tool::outputPolicy(bool overwrite) {
  granular::OutputPolicy policy;
  policy.overwrite = overwrite;
  if (const char* hint = std::getenv("GRANULAR_OVERWRITE_HINT"); hint != nullptr && *hint) {
    policy.overwrite_hint = hint;
  }
  return policy;
}

}  // namespace granular_ros
