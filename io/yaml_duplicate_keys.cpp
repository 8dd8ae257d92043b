// Duplicated YAML keys (see yaml_duplicate_keys.h).
#include "io/yaml_duplicate_keys.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <map>
#include <sstream>
#include <vector>

#include "io/input_error.h"

namespace xsect {

namespace {

/// Follows the nesting of mappings and lists; in each mapping, the keys met so far with their
/// lines.
class KeyRecorder : public YAML::EventHandler {
 public:
  explicit KeyRecorder(std::string file) : file_(std::move(file)) {}

  void OnDocumentStart(const YAML::Mark&) override { stack_.clear(); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { scalar(m, "~"); }
  // An alias as a key names another node's value, unknown here: not compared (a complex key).
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { node(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string& value) override {
    scalar(m, value);
  }
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(false);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(true);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Level {
    bool map = false;
    bool expect_key = true;            ///< map: the next node is a key
    bool complex_key = false;          ///< map: the key being read is a mapping or a list
    std::string key;                   ///< map: the current key; list: unused
    int index = 0;                     ///< list: the current item
    std::map<std::string, int> lines;  ///< map: keys met, with their 1-based lines
  };

  /// The dotted path to the node being read at the top level `upTo` (exclusive).
  std::string path(std::size_t upTo) const {
    std::string p;
    for (std::size_t i = 0; i < upTo; ++i) {
      const Level& l = stack_[i];
      if (l.map) p += (p.empty() ? "" : ".") + l.key;
      else p += "[" + std::to_string(l.index) + "]";
    }
    return p;
  }

  void scalar(const YAML::Mark& m, const std::string& value) {
    if (!stack_.empty() && stack_.back().map && stack_.back().expect_key) {
      Level& l = stack_.back();
      const int line = m.line + 1;
      if (value != "<<") {
        const auto [it, fresh] = l.lines.emplace(value, line);
        if (!fresh) {
          const std::string where = path(stack_.size() - 1);
          throw InputError(file_, (where.empty() ? "" : where + ".") + value,
                           "given twice (lines " + std::to_string(it->second) + " and " + std::to_string(line) +
                               "): a key may appear once in its mapping; merge the two or delete one",
                           line);
        }
      }
      l.key = value;
      l.complex_key = false;
    }
    done();
  }

  /// A node whose text is not a key to compare (an alias).
  void node(const YAML::Mark&) {
    if (!stack_.empty() && stack_.back().map && stack_.back().expect_key) {
      stack_.back().key = "?";
      stack_.back().complex_key = false;
    }
    done();
  }

  void open(bool map) {
    if (!stack_.empty() && stack_.back().map && stack_.back().expect_key) stack_.back().complex_key = true;
    Level l;
    l.map = map;
    stack_.push_back(std::move(l));
  }

  void close() {
    stack_.pop_back();
    if (!stack_.empty() && stack_.back().map && stack_.back().complex_key && stack_.back().expect_key)
      stack_.back().key = "?";
    done();
  }

  /// A whole node was read at the top level: a key or value of a mapping, an item of a list.
  void done() {
    if (stack_.empty()) return;
    Level& l = stack_.back();
    if (l.map) l.expect_key = !l.expect_key;
    else ++l.index;
  }

  std::string file_;
  std::vector<Level> stack_;
};

}  // namespace

void checkNoDuplicateKeys(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  KeyRecorder recorder(file);
  try {
    // The first document only, as YAML::Load reads. yaml-cpp 0.7's parser can return "another
    // document" forever on a stray token at document level without consuming it (found by the
    // slices, config, truth and poses fuzzers: a loop over documents never ended).
    YAML::Parser parser(in);
    parser.HandleNextDocument(recorder);
  } catch (const YAML::Exception&) {
    // Syntax errors: the loader reports them with its own message.
  }
}

}  // namespace xsect
