#include "client/mjpeg_page.h"

namespace viscera::client {
namespace {

// The title goes in between; the script reads it back from document.title (decoded).
constexpr const char* kHead = R"(<!doctype html>
<html><head><meta charset="utf-8"><meta name="viewport" content="width=device-width">
<title>)";

constexpr const char* kBody = R"(</title>
<style>
html,body{margin:0;height:100%;background:#111;color:#aaa;font:13px sans-serif}
body{display:flex;flex-direction:column;align-items:center;justify-content:center}
#stream{max-width:100%;max-height:calc(100vh - 40px);background:#000}
#status{margin-top:8px}
</style></head>
<body>
<img id="stream" src="stream.mjpg" alt="">
<div id="status"><span id="state">connecting</span> &middot; <span id="shown">0</span> frames shown</div>
<script>
(() => {
  const img = document.getElementById('stream');
  const shown = document.getElementById('shown');
  const state = document.getElementById('state');
  const title = document.title;
  // Same origin, so the canvas is not tainted and its pixels can be read.
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 32;
  const ctx = canvas.getContext('2d', {willReadFrequently: true});
  let count = 0, last = -1;
  setInterval(() => {
    if (img.naturalWidth > 0) {
      ctx.drawImage(img, 0, 0, 32, 32);
      const px = ctx.getImageData(0, 0, 32, 32).data;
      let h = 2166136261;  // FNV-1a over the thumbnail's RGB
      for (let i = 0; i < px.length; i += 4)
        h = Math.imul(h ^ px[i] ^ (px[i + 1] << 8) ^ (px[i + 2] << 16), 16777619) >>> 0;
      if (h !== last) { last = h; ++count; }
      state.textContent = 'live ' + img.naturalWidth + 'x' + img.naturalHeight;
    }
    shown.textContent = count;
    document.title = title + ' - ' + count + ' frames';
  }, 100);
  img.addEventListener('error', () => { state.textContent = 'stream ended'; });
})();
</script>
</body></html>
)";

}  // namespace

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string MjpegPage(const std::string& title) {
  return kHead + HtmlEscape(title) + kBody;
}

}  // namespace viscera::client
