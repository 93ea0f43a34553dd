//===- Messages.cpp - setmessage and getmessage within a batch ------------===//
//
// Each shading thread keeps the messages of the batch it runs: per message
// its type (as the kinds of its rows), where it was first set, and per lane
// whether it is set, its rows, and where a getmessage that found nothing
// asked for it. Errors are reported per point among the point's prints,
// in OSL's words.
//
//===----------------------------------------------------------------------===//
#include "OslAbi/EntryPoints.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/StringCall.h"

#include <string>
#include <vector>

namespace {

struct Message {
  std::string name;
  /// Empty until a setmessage gives the message a type.
  std::string kinds, typeName, setWhere;
  int32_t width = 0;
  std::vector<int32_t> rows; // rowCount x width
  std::vector<bool> isSet;
  std::vector<std::string> queriedWhere; // per lane; "" if never asked
};

std::vector<Message> &threadMessages() {
  thread_local std::vector<Message> messages;
  return messages;
}

int32_t rowCount(const std::string &kinds) {
  int32_t n = 0;
  for (char k : kinds)
    n += osl::stringOperandRows(k);
  return n;
}

Message *findMessage(const char *name) {
  for (Message &m : threadMessages())
    if (m.name == name)
      return &m;
  return nullptr;
}

/// The message `name`, made (unset on every lane) if there is none.
Message &messageNamed(const char *name, int32_t width) {
  if (Message *found = findMessage(name))
    return *found;
  Message m;
  m.name = name;
  m.width = width;
  m.isSet.assign(width, false);
  m.queriedWhere.assign(width, "");
  threadMessages().push_back(std::move(m));
  return threadMessages().back();
}

void report(int32_t lane, const std::string &text) {
  osl::keepLaneText(osl::printStreamCode("renderer_error"), lane, "", text);
}

} // namespace

extern "C" void osl_rt_message_reset() { threadMessages().clear(); }

extern "C" void osl_rt_setmessage(const char *where, const char *name, const char *typeName,
                                  const char *kinds, const int32_t *rows, int32_t width,
                                  uint32_t laneMask) {
  Message &m = messageNamed(name, width);
  int32_t count = rowCount(kinds);
  if (m.kinds.empty()) {
    m.kinds = kinds;
    m.typeName = typeName;
    m.setWhere = where;
    m.rows.assign(size_t(count) * size_t(width), 0);
  }
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1u))
      continue;
    if (m.isSet[lane]) {
      report(lane, "message \"" + m.name + "\" already exists (created here: " + m.setWhere +
                       ") cannot set again from " + where);
      continue;
    }
    if (!m.queriedWhere[lane].empty()) {
      report(lane, "message \"" + m.name + "\" was queried before being set (queried here: " +
                       m.queriedWhere[lane] + ") setting it now (" + where +
                       ") would lead to inconsistent results");
      continue;
    }
    if (m.kinds != kinds) { // set with another type on other points
      report(lane, "type mismatch for message \"" + m.name + "\" (created as " + m.typeName +
                       " here: " + m.setWhere + ") cannot set as " + typeName + " from " +
                       where);
      continue;
    }
    for (int32_t r = 0; r < count; ++r)
      m.rows[size_t(r) * width + lane] = rows[size_t(r) * width + lane];
    m.isSet[lane] = true;
  }
}

extern "C" void osl_rt_getmessage(const char *where, const char *name, const char *typeName,
                                  const char *kinds, int32_t *rows, int32_t width,
                                  uint32_t laneMask) {
  int32_t count = rowCount(kinds);
  int32_t *found = rows + size_t(count) * width;
  Message *m = findMessage(name);
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1u))
      continue;
    found[lane] = 0;
    if (!m || !m->isSet[lane]) {
      Message &asked = m ? *m : messageNamed(name, width);
      m = &asked;
      if (asked.queriedWhere[lane].empty())
        asked.queriedWhere[lane] = where;
      continue;
    }
    if (m->kinds != kinds) {
      report(lane, "type mismatch for message \"" + m->name + "\" (created as " + m->typeName +
                       " here: " + m->setWhere + ") cannot fetch as " + typeName + " from " +
                       where);
      continue;
    }
    for (int32_t r = 0; r < count; ++r)
      rows[size_t(r) * width + lane] = m->rows[size_t(r) * width + lane];
    found[lane] = 1;
  }
}
