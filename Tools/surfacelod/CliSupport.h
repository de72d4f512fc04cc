// Small helpers of the `surfacelod` tool: errors with exit codes, option parsing, JSON lines,
// timing, peak memory and a terminal progress bar.
#ifndef surfacelodCliSupport_h
#define surfacelodCliSupport_h

#include <chrono>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

class vtkAlgorithm;

namespace slodcli
{
// Exit codes: 0 success, 1 wrong usage, 2 a file or its contents could not be used, 3 other failure.
enum ExitCode
{
  ExitSuccess = 0,
  ExitUsage = 1,
  ExitData = 2,
  ExitFailure = 3
};

// A failure reported to the user as one line on stderr, then exit with Code.
struct CliError : std::runtime_error
{
  CliError(int code, const std::string& message)
    : std::runtime_error(message)
    , Code(code)
  {
  }
  int Code;
};

struct OptionSpec
{
  std::string Name;    // without the leading "--"
  std::string Value;   // placeholder of the value ("N"), empty for a flag
  std::string Help;
};

struct CommandSpec
{
  std::string Name;
  std::string Usage;       // "INPUT OUTPUT --method NAME ..."
  std::string Description; // paragraph(s) shown by --help
  std::vector<std::string> Positionals;
  std::vector<OptionSpec> Options;
};

class ParsedArguments
{
public:
  std::vector<std::string> Positionals;
  bool Has(const std::string& name) const { return this->Values.count(name) > 0; }
  // The value of an option (the last one when it was given several times).
  std::string Get(const std::string& name, const std::string& fallback = std::string()) const;
  // Every value of an option given several times, in order (--input A --input B).
  std::vector<std::string> GetAll(const std::string& name) const;
  long long GetInteger(const std::string& name, long long fallback, long long minimum, long long maximum) const;
  double GetReal(const std::string& name, double fallback, double minimum, double maximum) const;
  std::map<std::string, std::string> Values;
  std::map<std::string, std::vector<std::string>> AllValues;
  std::string Command;
};

// Parses argv[first..argc) against the spec. Returns false when --help was asked (help printed).
// Throws CliError(ExitUsage) on unknown options, missing values or a wrong number of positionals.
bool ParseArguments(const CommandSpec& spec, int argc, char* argv[], int first, ParsedArguments& out);
void PrintCommandHelp(const CommandSpec& spec);

std::vector<std::string> SplitList(const std::string& text, char separator = ',');

// One JSON object on one line, keys in insertion order.
class JsonLine
{
public:
  JsonLine& Add(const std::string& key, const std::string& value);
  JsonLine& Add(const std::string& key, const char* value) { return this->Add(key, std::string(value)); }
  JsonLine& Add(const std::string& key, long long value);
  JsonLine& Add(const std::string& key, double value); // NaN/Inf -> null
  JsonLine& Add(const std::string& key, bool value);
  JsonLine& AddNull(const std::string& key);
  std::string Str() const { return "{" + this->Body + "}"; }
  void Print() const; // to stdout, with newline, flushed

private:
  void Key(const std::string& key);
  std::string Body;
};

std::string FormatReal(double value, int significant = 6);

class Stopwatch
{
public:
  Stopwatch()
    : Start(std::chrono::steady_clock::now())
  {
  }
  double Seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - this->Start).count();
  }

private:
  std::chrono::steady_clock::time_point Start;
};

// Peak resident set size of this process in MiB (VmHWM, else getrusage).
double PeakResidentMegabytes();

// Draws "label [#####     ]  45%" on stderr while the algorithm reports progress, only when
// stderr is a terminal. Detaches and clears the line when destroyed.
class ProgressBar
{
public:
  ProgressBar(vtkAlgorithm* algorithm, const std::string& label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void Draw(double fraction);

private:
  vtkAlgorithm* Algorithm = nullptr;
  unsigned long Tag = 0;
  std::string Label;
  int LastPercent = -1;
  bool Enabled = false;
};
} // namespace slodcli

#endif
