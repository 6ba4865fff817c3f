#include "pf2/core/app_settings.h"

#include <iostream>

#include "pf2/core/command_line.h"
#include "pf2/core/config_file.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"

namespace pf2 {

const char* const kSettingsUsage =
    "  --config FILE        'key value' settings, one per line (--settings lists the keys)\n"
    "  --set KEY=VALUE      one setting, after --config (repeatable)\n"
    "  --settings           print every setting (key, default, unit, allowed values, meaning) and exit\n";

bool answeredHelpOrSettings(CommandLine* cli, const std::string& usage, const Settings& settings) {
  if (cli->helpRequested()) {
    std::cout << usage;
    return true;
  }
  if (cli->flag("--settings")) {
    std::cout << settings.markdown();
    return true;
  }
  return false;
}

void readCommandLineSettings(CommandLine* cli, Settings* settings, const std::vector<SettingShortcut>& shortcuts) {
  if (const auto config_path = cli->value("--config")) settings->apply(ConfigFile::load(*config_path));
  for (const std::string& assignment : cli->values("--set")) settings->setAssignment(assignment);
  for (const SettingShortcut& shortcut : shortcuts) {
    std::optional<std::string> value;
    if (shortcut.fixed_value) {
      if (cli->flag(shortcut.option)) value = shortcut.fixed_value;
    } else {
      value = cli->value(shortcut.option);
    }
    if (!value) continue;
    try {
      settings->set(shortcut.key, *value);
    } catch (const Error& e) {
      throw Error("option " + shortcut.option + ": " + e.what());
    }
  }
  settings->validate();
}

}  // namespace pf2
