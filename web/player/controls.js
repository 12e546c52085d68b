// The player's keyboard, fullscreen and drag-and-drop, as a video player has them (the keys
// are listed in index.html's panel).  The player passes in what each one does.

export function toggleFullscreen() {
  if (document.fullscreenElement) document.exitFullscreen().catch(() => {});
  else document.documentElement.requestFullscreen?.().catch(() => {});
}

// actions: { togglePlay(), step(n), first(), last(), resetView(), toggleLoop() }
export function installKeyboard(scrub, actions) {
  // A mouse click leaves the button focused: Space would press it again instead of playing.
  for (const button of document.querySelectorAll('button')) button.addEventListener('click', () => button.blur());
  window.addEventListener('keydown', (e) => {
    const target = e.target;
    if (target instanceof HTMLSelectElement || e.ctrlKey || e.metaKey || e.altKey) return;
    if (target instanceof HTMLInputElement && target.type !== 'range' && target.type !== 'checkbox') return;
    // A focused button takes Space and Enter itself; the scrub bar moves with the arrows itself.
    if ((target instanceof HTMLButtonElement || target.type === 'checkbox') && (e.key === ' ' || e.key === 'Enter')) return;
    if (target === scrub && ['ArrowLeft', 'ArrowRight', 'Home', 'End', 'PageUp', 'PageDown'].includes(e.key)) return;
    const step = e.shiftKey ? 10 : 1;
    const key = e.key.length === 1 ? e.key.toLowerCase() : e.key;
    const keys = {
      ' ': actions.togglePlay,
      ArrowRight: () => actions.step(step),
      ArrowLeft: () => actions.step(-step),
      Home: actions.first,
      End: actions.last,
      r: actions.resetView,
      f: toggleFullscreen,
      l: actions.toggleLoop,
    };
    if (!keys[key]) return;
    e.preventDefault();
    keys[key]();
  });
}

// Calls onFile(File) for a file dropped anywhere on the page, showing `hint` while one is dragged.
export function installDrop(hint, onFile) {
  let depth = 0;  // dragenter/dragleave fire for every element crossed
  document.addEventListener('dragenter', (e) => { e.preventDefault(); depth++; hint.hidden = false; });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('dragleave', () => { if (--depth <= 0) { depth = 0; hint.hidden = true; } });
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    hint.hidden = true;
    onFile(e.dataTransfer?.files?.[0]);
  });
}
