#pragma once
/// The viewer page that MjpegServer serves at "/".
#include <string>

namespace viscera::client {

/// `text` with & < > " ' replaced by character references, safe in HTML text and attributes.
std::string HtmlEscape(const std::string& text);

/// A self-contained HTML page (no external resources) titled `title`: the stream
/// `<img id="stream" src="stream.mjpg">` centred on a dark background, and a status line.
/// Its script counts, every 100 ms, how many times the picture changed (a hash of a 32x32
/// thumbnail drawn through a canvas), writes the count into `<span id="shown">` and sets
/// document.title to "<title> - N frames"; the headless-Chromium check reads that count.
std::string MjpegPage(const std::string& title);

}  // namespace viscera::client
