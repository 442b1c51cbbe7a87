// zros view: lists sensor_msgs/msg/Image topics and shows the selected one live.
// Frames come from /frame.png as a long poll (after=<last seq>), one request at a time, so
// the browser gets every frame it can draw and never queues stale ones.
'use strict';

const select = document.getElementById('topic');
const img = document.getElementById('frame');
const statusText = document.getElementById('status');
const message = document.getElementById('message');

let topic = JSON.parse(document.body.dataset.initialTopic || 'null');
let seq = 0;
let generation = 0;           // bumps when the topic changes: stale responses are dropped
let frames = 0;
let lastRateAt = performance.now();
let info = '';

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

function showMessage(text) {
  message.textContent = text;
  message.hidden = !text;
}

function chooseTopic(name) {
  if (name === topic) return;
  topic = name;
  seq = 0;
  generation += 1;
  info = '';
  const url = new URL(window.location.href);
  if (topic) url.searchParams.set('topic', topic); else url.searchParams.delete('topic');
  history.replaceState(null, '', url);
}

select.addEventListener('change', () => chooseTopic(select.value || null));

async function refreshTopics() {
  try {
    const response = await fetch('api/topics', { cache: 'no-store' });
    const data = await response.json();
    const names = data.topics.map((t) => t.name);
    if (!topic && data.default) chooseTopic(data.default);
    if (topic && !names.includes(topic)) names.unshift(topic);
    const current = Array.from(select.options).map((o) => o.value);
    if (names.join('\n') !== current.join('\n')) {
      select.replaceChildren(...names.map((name) => new Option(name, name)));
    }
    select.value = topic || '';
    if (!names.length) showMessage('No sensor_msgs/msg/Image topic in the graph yet.');
  } catch (err) {
    statusText.textContent = 'server unreachable';
  }
}

async function frameLoop() {
  for (;;) {
    if (!topic) { await sleep(500); continue; }
    const mine = generation;
    const url = `frame.png?topic=${encodeURIComponent(topic)}&after=${seq}&timeout=2`;
    try {
      const response = await fetch(url, { cache: 'no-store' });
      if (mine !== generation) continue;
      if (response.status === 204) { statusText.textContent = `${topic}: waiting for frames`; continue; }
      if (!response.ok) {
        showMessage(await response.text());
        await sleep(1000);
        continue;
      }
      seq = Number(response.headers.get('X-Frame-Seq')) || seq + 1;
      info = `${response.headers.get('X-Frame-Width')}\u00d7${response.headers.get('X-Frame-Height')} ` +
             `${response.headers.get('X-Frame-Encoding')}`;
      const blobUrl = URL.createObjectURL(await response.blob());
      const old = img.src;
      img.src = blobUrl;
      try { await img.decode(); } catch (err) { /* shown anyway */ }
      if (old.startsWith('blob:')) URL.revokeObjectURL(old);
      showMessage('');
      frames += 1;
    } catch (err) {
      statusText.textContent = 'server unreachable, retrying';
      await sleep(1000);
    }
  }
}

setInterval(() => {
  const now = performance.now();
  const fps = (frames * 1000) / (now - lastRateAt);
  frames = 0;
  lastRateAt = now;
  if (topic && info) statusText.textContent = `${info}, ${fps.toFixed(1)} fps`;
}, 1000);

refreshTopics();
setInterval(refreshTopics, 2000);
frameLoop();
