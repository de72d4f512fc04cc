#include "CliSupport.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkNew.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>

namespace slodcli
{
std::string ParsedArguments::Get(const std::string& name, const std::string& fallback) const
{
  auto it = this->Values.find(name);
  return it == this->Values.end() ? fallback : it->second;
}

std::vector<std::string> ParsedArguments::GetAll(const std::string& name) const
{
  auto it = this->AllValues.find(name);
  return it == this->AllValues.end() ? std::vector<std::string>() : it->second;
}

long long ParsedArguments::GetInteger(
  const std::string& name, long long fallback, long long minimum, long long maximum) const
{
  auto it = this->Values.find(name);
  if (it == this->Values.end())
  {
    return fallback;
  }
  const std::string& text = it->second;
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE)
  {
    throw CliError(ExitUsage, "--" + name + ": '" + text + "' is not an integer");
  }
  if (value < minimum || value > maximum)
  {
    throw CliError(ExitUsage,
      "--" + name + ": " + text + " is out of range [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]");
  }
  return value;
}

double ParsedArguments::GetReal(const std::string& name, double fallback, double minimum, double maximum) const
{
  auto it = this->Values.find(name);
  if (it == this->Values.end())
  {
    return fallback;
  }
  const std::string& text = it->second;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value))
  {
    throw CliError(ExitUsage, "--" + name + ": '" + text + "' is not a number");
  }
  if (value < minimum || value > maximum)
  {
    throw CliError(ExitUsage,
      "--" + name + ": " + text + " is out of range [" + FormatReal(minimum) + ", " + FormatReal(maximum) + "]");
  }
  return value;
}

void PrintCommandHelp(const CommandSpec& spec)
{
  std::cout << "usage: surfacelod " << spec.Name << " " << spec.Usage << "\n\n" << spec.Description << "\n";
  if (!spec.Options.empty())
  {
    std::cout << "\noptions:\n";
    for (const OptionSpec& o : spec.Options)
    {
      std::string left = "  --" + o.Name + (o.Value.empty() ? "" : " " + o.Value);
      if (left.size() < 28)
      {
        left.resize(28, ' ');
        std::cout << left << o.Help << "\n";
      }
      else
      {
        std::cout << left << "\n" << std::string(28, ' ') << o.Help << "\n";
      }
    }
    std::cout << "  --help                    show this help\n";
  }
}

bool ParseArguments(const CommandSpec& spec, int argc, char* argv[], int first, ParsedArguments& out)
{
  out.Command = spec.Name;
  const std::string context = "surfacelod " + spec.Name + ": ";
  for (int i = first; i < argc; ++i)
  {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h")
    {
      PrintCommandHelp(spec);
      return false;
    }
    if (arg.size() > 2 && arg.compare(0, 2, "--") == 0)
    {
      std::string name = arg.substr(2), value;
      const size_t eq = name.find('=');
      const bool inlineValue = eq != std::string::npos;
      if (inlineValue)
      {
        value = name.substr(eq + 1);
        name.erase(eq);
      }
      const OptionSpec* option = nullptr;
      for (const OptionSpec& o : spec.Options)
      {
        if (o.Name == name)
        {
          option = &o;
        }
      }
      if (!option)
      {
        throw CliError(ExitUsage, context + "unknown option --" + name + " (see --help)");
      }
      if (option->Value.empty())
      {
        if (inlineValue)
        {
          throw CliError(ExitUsage, context + "--" + name + " takes no value");
        }
        value = "1";
      }
      else if (!inlineValue)
      {
        if (i + 1 >= argc)
        {
          throw CliError(ExitUsage, context + "--" + name + " needs a value " + option->Value);
        }
        value = argv[++i];
      }
      out.Values[name] = value;
      out.AllValues[name].push_back(value);
    }
    else
    {
      out.Positionals.push_back(arg);
    }
  }
  if (out.Positionals.size() != spec.Positionals.size())
  {
    std::string expected;
    for (const std::string& p : spec.Positionals)
    {
      expected += (expected.empty() ? "" : " ") + p;
    }
    throw CliError(ExitUsage,
      context + "expected " + (expected.empty() ? std::string("no file arguments") : expected) + ", got " +
        std::to_string(out.Positionals.size()) + " argument(s) (see --help)");
  }
  return true;
}

std::vector<std::string> SplitList(const std::string& text, char separator)
{
  std::vector<std::string> items;
  std::string item;
  std::istringstream s(text);
  while (std::getline(s, item, separator))
  {
    if (!item.empty())
    {
      items.push_back(item);
    }
  }
  return items;
}

namespace
{
std::string JsonEscape(const std::string& text)
{
  std::string out;
  for (unsigned char c : text)
  {
    switch (c)
    {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20)
        {
          char buffer[8];
          std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
          out += buffer;
        }
        else
        {
          out += static_cast<char>(c);
        }
    }
  }
  return out;
}
} // namespace

void JsonLine::Key(const std::string& key)
{
  if (!this->Body.empty())
  {
    this->Body += ", ";
  }
  this->Body += "\"" + JsonEscape(key) + "\": ";
}

JsonLine& JsonLine::Add(const std::string& key, const std::string& value)
{
  this->Key(key);
  this->Body += "\"" + JsonEscape(value) + "\"";
  return *this;
}

JsonLine& JsonLine::Add(const std::string& key, long long value)
{
  this->Key(key);
  this->Body += std::to_string(value);
  return *this;
}

JsonLine& JsonLine::Add(const std::string& key, bool value)
{
  this->Key(key);
  this->Body += value ? "true" : "false";
  return *this;
}

JsonLine& JsonLine::Add(const std::string& key, double value)
{
  this->Key(key);
  this->Body += std::isfinite(value) ? FormatReal(value, 9) : std::string("null");
  return *this;
}

JsonLine& JsonLine::AddNull(const std::string& key)
{
  this->Key(key);
  this->Body += "null";
  return *this;
}

void JsonLine::Print() const
{
  std::cout << this->Str() << std::endl;
}

std::string FormatReal(double value, int significant)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

double PeakResidentMegabytes()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.compare(0, 6, "VmHWM:") == 0)
    {
      return std::strtod(line.c_str() + 6, nullptr) / 1024.0; // kB
    }
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0; // kB on Linux
}

namespace
{
void OnProgress(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* bar = static_cast<ProgressBar*>(clientData);
  bar->Draw(static_cast<vtkAlgorithm*>(caller)->GetProgress());
}
} // namespace

ProgressBar::ProgressBar(vtkAlgorithm* algorithm, const std::string& label)
  : Algorithm(algorithm)
  , Label(label)
  , Enabled(algorithm && isatty(STDERR_FILENO))
{
  if (this->Enabled)
  {
    vtkNew<vtkCallbackCommand> callback;
    callback->SetCallback(OnProgress);
    callback->SetClientData(this);
    this->Tag = algorithm->AddObserver(vtkCommand::ProgressEvent, callback);
  }
}

ProgressBar::~ProgressBar()
{
  if (this->Enabled)
  {
    this->Algorithm->RemoveObserver(this->Tag);
    if (this->LastPercent >= 0)
    {
      std::fprintf(stderr, "\r%*s\r", static_cast<int>(this->Label.size()) + 40, "");
      std::fflush(stderr);
    }
  }
}

void ProgressBar::Draw(double fraction)
{
  const int percent = static_cast<int>(std::lround(100.0 * std::min(1.0, std::max(0.0, fraction))));
  if (percent == this->LastPercent)
  {
    return;
  }
  this->LastPercent = percent;
  constexpr int width = 30;
  const int filled = percent * width / 100;
  std::fprintf(stderr, "\r%s [%s%s] %3d%%", this->Label.c_str(), std::string(size_t(filled), '#').c_str(),
    std::string(size_t(width - filled), ' ').c_str(), percent);
  std::fflush(stderr);
}
} // namespace slodcli
