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
#stream,#scene{max-width:100%;max-height:calc(100vh - 40px);background:#000}
#status{margin-top:8px}
#warn{color:#f84;font-weight:bold}
a{color:#8af}
</style></head>
<body>
<canvas id="scene" hidden></canvas>
<img id="stream" alt="" hidden>
<div id="status"><span id="mode">-</span> &middot; <span id="state">connecting</span> &middot;
<span id="shown">0</span> frames shown &middot; <span id="fps">0</span> fps &middot; age <span id="age">-</span> ms
<span id="warn"></span> &middot; <a id="switch" href="?video=server">server frames</a></div>
<script src="viewer.js"></script>
<script>
(() => {
  const $ = (id) => document.getElementById(id);
  const img = $('stream'), canvas = $('scene'), shown = $('shown'), state = $('state');
  const title = document.title;
  const asked = new URLSearchParams(location.search).get('video');
  let count = 0;
  const show = (fps, age_ms, note, late) => {
    $('fps').textContent = fps.toFixed(1);
    $('age').textContent = age_ms < 0 ? '-' : Math.round(age_ms);
    state.textContent = note;
    $('warn').textContent = late;
    shown.textContent = count;
    document.title = title + ' - ' + count + ' frames';
  };

  // Server frames: the MJPEG stream in an <img>. Every 100 ms the picture is hashed (a 32x32
  // thumbnail through a canvas, same origin so readable) to count the frames that changed;
  // the viewer's /stats.json says how old and how frequent the frames are.
  function ServerFrames() {
    $('mode').textContent = 'server frames';
    $('switch').textContent = 'draw here';
    $('switch').href = '?video=client';
    img.hidden = false;
    img.src = 'stream.mjpg';
    const thumb = document.createElement('canvas');
    thumb.width = thumb.height = 32;
    const ctx = thumb.getContext('2d', {willReadFrequently: true});
    let last = -1, stats = null, ended = false;
    img.addEventListener('error', () => { ended = true; });
    setInterval(() => {
      fetch('stats.json').then((r) => r.json()).then((s) => { stats = s; }).catch(() => { stats = null; });
    }, 500);
    setInterval(() => {
      if (img.naturalWidth > 0) {
        ctx.drawImage(img, 0, 0, 32, 32);
        const px = ctx.getImageData(0, 0, 32, 32).data;
        let h = 2166136261;  // FNV-1a over the thumbnail's RGB
        for (let i = 0; i < px.length; i += 4)
          h = Math.imul(h ^ px[i] ^ (px[i + 1] << 8) ^ (px[i + 2] << 16), 16777619) >>> 0;
        if (h !== last) { last = h; ++count; }
      }
      let note = ended ? 'stream ended' : img.naturalWidth > 0 ? 'live ' + img.naturalWidth + 'x' + img.naturalHeight : 'connecting';
      let late = '', fps = 0, age = -1;
      if (stats && stats.frame_step >= 0) {
        fps = stats.frame_rate_hz;
        age = stats.frame_age_ms + stats.since_frame_ms;
        if (stats.since_frame_ms > 1000) {
          note = 'stream paused (no frame for ' + (stats.since_frame_ms / 1000).toFixed(1) + ' s)';
        }
        if (age > 250) late = 'late: the picture is ' + (age / 1000).toFixed(2) + ' s old';
      }
      show(fps, age, note, late);
    }, 100);
  }

  // Drawn here: the scene once, then skeleton states over a WebSocket, drawn at the display's rate.
  function DrawHere(scene) {
    $('mode').textContent = 'drawn here (WebGL)';
    canvas.hidden = false;
    const player = new Viewer.Player(canvas, scene);
    window.viscera = player;
    let socket_open = false, gone = 0;
    const connect = () => {
      const socket = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/skeleton');
      socket.onopen = () => { socket_open = true; };
      socket.onmessage = (event) => player.Receive(event.data);
      socket.onclose = () => { socket_open = false; ++gone; setTimeout(connect, 1000); };
    };
    connect();
    const frame = (now) => {
      player.Frame(now);
      count = player.changed;
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
    setInterval(() => {
      const now = performance.now(), r = player.Rates(now), last = player.latest;
      let note = socket_open ? 'live' : gone > 0 ? 'reconnecting' : 'connecting', late = '', age = -1;
      if (last !== null) {
        const silent = now - Math.max(last.arrived, last.arrived_same || 0);
        age = last.age_ms + silent;
        if (silent > 1000) {
          note = 'stream paused (no state for ' + (silent / 1000).toFixed(1) + ' s): still drawing the last';
        } else if (last.arrived_same && now - last.arrived > 1000) {
          note = 'session paused at ' + last.t.toFixed(2) + ' s';
        } else {
          note += ' t = ' + last.t.toFixed(2) + ' s, ' + r.states_hz.toFixed(0) + ' states/s';
        }
        if (age > 250) late = 'late: the state shown is ' + (age / 1000).toFixed(2) + ' s old';
      }
      player.note = note;
      show(r.fps, age, note, late);
    }, 250);
  }

  if (asked === 'server') { ServerFrames(); return; }
  const load = () => fetch('scene.json').then((r) => {
    if (r.status === 503) { setTimeout(load, 500); return; }
    if (!r.ok) { ServerFrames(); return; }  // this viewer has no scene
    return r.json().then(DrawHere);
  }).catch((e) => { state.textContent = 'cannot draw here: ' + e; ServerFrames(); });
  load();
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

std::string MjpegPage(const std::string& title) { return kHead + HtmlEscape(title) + kBody; }

}  // namespace viscera::client
