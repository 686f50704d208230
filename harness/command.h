#pragma once
// svr's subcommands. Each *_command.cpp defines its own: name, one-line help, and a function
// that adds its flags to a CLI11 subcommand and sets the callback that runs it. commands.cpp
// holds the one list of them (as renderers/registry.cpp does for backends), and svr_main.cpp
// only dispatches: adding a command is its file plus one line in that list.

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace svr {

// What every command sees: the global flags, and where it leaves its exit status.
class RenderDistribution;

struct CommandContext {
  std::string data_dir;
  int status = 0;
  // svr-mpi: the process's part in a distributed render (harness/render_distribution.h).
  RenderDistribution* distribution = nullptr;
};

struct CommandEntry {
  std::string name, help;
  // Adds the flags to `sub` and sets sub's callback. The options live in the closure, so they
  // last as long as the App.
  std::function<void(CLI::App& sub, CommandContext& context)> define;
};

const std::vector<CommandEntry>& commandEntries();

// Sets sub's callback to run `run` on the parsed options, with the global data folder, keeping
// its exit status: the callback of every command that checks nothing more itself.
template <class Options, class App>
void runOnParse(App& sub, CommandContext& context, std::shared_ptr<Options> options,
                int (*run)(const Options&)) {
  sub.callback([options, run, &context] {
    options->data_dir = context.data_dir;
    context.status = run(*options);
  });
}

// --no-cache on a command that loads scenes: train models and design palettes afresh, and
// neither read nor write the disk cache (base/disk_cache.h).
void addCacheFlag(CLI::App& sub);

// An image size given on the command line: the scene file's image.width/height range, checked
// before any loading or rendering ("render: --width 0 is outside 1..16384").
void checkImageSize(const std::string& command, const std::string& flag, int value);

}  // namespace svr
