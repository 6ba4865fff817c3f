#pragma once
// How every pf2_* app reads its settings from the command line, in one order:
//   1. --config FILE      'key value' lines (ConfigFile), unknown keys refused
//   2. --set KEY=VALUE    repeatable, in the order given
//   3. shortcut options   e.g. `pf2_synth --frames 60` is `--set synth.frames=60`
// then Settings::validate(). A shortcut names its option in errors ("option --frames: setting
// synth.frames = -5: expected an integer in [1, 1000000]"), so the user sees what they typed.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pf2 {

class CommandLine;
class Settings;

// A command-line option that stands for one setting. Without `fixed_value` it takes an argument
// (`--frames N`); with one it is a flag that sets that value (`--blur` sets synth.blur=true).
struct SettingShortcut {
  SettingShortcut(std::string option_name, std::string setting_key)
      : option(std::move(option_name)), key(std::move(setting_key)) {}
  SettingShortcut(std::string option_name, std::string setting_key, std::string value)
      : option(std::move(option_name)), key(std::move(setting_key)), fixed_value(std::move(value)) {}

  std::string option;
  std::string key;
  std::optional<std::string> fixed_value;
};

// Reads --config, --set and the shortcuts from `cli` (consuming them) into `settings`, then
// validates. Throws pf2::Error naming the option or key, the value and the allowed range.
void readCommandLineSettings(CommandLine* cli, Settings* settings,
                             const std::vector<SettingShortcut>& shortcuts = {});

// Answers the two questions an app's command line can ask before any work: --help / -h prints
// `usage`, --settings prints the settings table (key, default, unit, allowed values, meaning).
// Returns true when it answered one (the app then exits 0).
bool answeredHelpOrSettings(CommandLine* cli, const std::string& usage, const Settings& settings);

// The usage lines every app prints for --config, --set and --settings.
extern const char* const kSettingsUsage;

}  // namespace pf2
