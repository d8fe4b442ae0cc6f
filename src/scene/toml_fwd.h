#pragma once
/// toml++'s table and node, declared for the scene's table readers' headers, which only pass it by
/// reference (toml++'s own header is heavy; the readers' .cc files include it).
namespace toml {
inline namespace v3 {
class table;
class node;
}  // namespace v3
}  // namespace toml
