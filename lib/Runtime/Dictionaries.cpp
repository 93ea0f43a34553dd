//===- Dictionaries.cpp - XML dictionaries queried with XPath -------------===//
#include "Dictionaries.h"

// OpenImageIO's copy of pugixml, header-only, with XPath (the scene reader
// includes it with the same configuration).
#define PUGIXML_NO_EXCEPTIONS
#include <OpenImageIO/detail/pugixml/pugixml.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

namespace {

struct Node {
  pugi::xml_node node;
  int32_t next = 0; // the query's next match, 0 after the last
};

struct Store {
  std::mutex mutex;
  /// Each dictionary once: its document, or null when it did not parse.
  std::map<std::string, std::unique_ptr<pugi::xml_document>, std::less<>> documents;
  std::map<std::string, std::string, std::less<>> documentErrors;
  /// Node id k is nodes[k - 1].
  std::vector<Node> nodes;
  /// (document or parent node, query) -> its first match's id (0: none).
  std::map<std::tuple<const void *, int32_t, std::string>, int32_t> queries;
};

Store &store() {
  static Store *s = new Store(); // ids outlive every kernel
  return *s;
}

/// Runs `query` from `from`, numbering its matches; caller holds the lock.
int32_t runQuery(Store &s, const void *document, int32_t parent, const pugi::xml_node &from,
                 std::string_view query, std::string &error) {
  auto key = std::make_tuple(document, parent, std::string(query));
  if (auto it = s.queries.find(key); it != s.queries.end())
    return it->second;
  pugi::xpath_query compiled(std::string(query).c_str());
  if (!compiled) {
    error = "dict_find: bad query \"" + std::string(query) + "\": " +
            compiled.result().description();
    return s.queries[key] = -1;
  }
  pugi::xpath_node_set matches = compiled.evaluate_node_set(from);
  int32_t first = 0;
  for (const pugi::xpath_node &m : matches) {
    pugi::xml_node node = m.node() ? m.node() : m.parent();
    if (!node)
      continue;
    s.nodes.push_back({node, 0});
    int32_t id = int32_t(s.nodes.size());
    if (first == 0)
      first = id;
    else
      s.nodes[size_t(id) - 2].next = id;
  }
  return s.queries[key] = first;
}

} // namespace

int32_t osl::dictFind(std::string_view dictionary, std::string_view query, std::string &error) {
  Store &s = store();
  std::lock_guard<std::mutex> lock(s.mutex);
  auto it = s.documents.find(dictionary);
  if (it == s.documents.end()) {
    auto doc = std::make_unique<pugi::xml_document>();
    std::string text(dictionary);
    pugi::xml_parse_result parsed = !text.empty() && text[0] == '<'
                                        ? doc->load_string(text.c_str())
                                        : doc->load_file(text.c_str());
    if (!parsed) {
      // As OSL words it.
      s.documentErrors[text] = std::string("XML parsed with errors: ") + parsed.description() +
                               ", at offset " + std::to_string(parsed.offset);
      doc.reset();
    }
    it = s.documents.emplace(text, std::move(doc)).first;
  }
  if (!it->second) {
    error = s.documentErrors[it->first];
    return -1;
  }
  return runQuery(s, it->second.get(), 0, *it->second, query, error);
}

int32_t osl::dictFindBelow(int32_t node, std::string_view query, std::string &error) {
  Store &s = store();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (node <= 0 || size_t(node) > s.nodes.size())
    return 0;
  pugi::xml_node from = s.nodes[size_t(node) - 1].node;
  return runQuery(s, nullptr, node, from, query, error);
}

int32_t osl::dictNext(int32_t node) {
  Store &s = store();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (node <= 0 || size_t(node) > s.nodes.size())
    return 0;
  return s.nodes[size_t(node) - 1].next;
}

bool osl::dictAttribute(int32_t node, std::string_view name, std::string &text) {
  Store &s = store();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (node <= 0 || size_t(node) > s.nodes.size())
    return false;
  pugi::xml_attribute a = s.nodes[size_t(node) - 1].node.attribute(std::string(name).c_str());
  if (!a)
    return false;
  text = a.value();
  return true;
}
