//===- Dictionaries.h - dict_find, dict_next, dict_value ---------*- C++ -*-===//
//
// OSL's dictionaries: XML given as text or a file name, queried with XPath.
// A query's matches get consecutive node ids (0: no match, -1: the
// dictionary could not be read); dict_next steps through them. Ids live as
// long as the process; the same query on the same node answers the same
// ids.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_DICTIONARIES_H
#define OSLRUNTIME_DICTIONARIES_H

#include <cstdint>
#include <string>
#include <string_view>

namespace osl {

/// The first node `query` matches in `dictionary` (XML text if it starts
/// with '<', else a file name); -1 with `error` set when it cannot be read.
int32_t dictFind(std::string_view dictionary, std::string_view query, std::string &error);
/// The first node `query` matches below node `node`.
int32_t dictFindBelow(int32_t node, std::string_view query, std::string &error);
/// The next match of the query that found `node`, or 0.
int32_t dictNext(int32_t node);
/// Attribute `name` of node `node`'s element (false when there is none).
bool dictAttribute(int32_t node, std::string_view name, std::string &text);

} // namespace osl

#endif // OSLRUNTIME_DICTIONARIES_H
