// The course's own highlight.js: none. Its code blocks are commands, TOML answers and output
// (`text`), which highlight.js leaves as they are; the stock file is 46 KB gzipped on every
// page's first visit, more than the margin the page keeps under its 1.5 MB budget. mdBook's
// book.js calls these two and gives every block the `hljs` class (its colours) itself.
window.hljs = {
  configure: function () {},
  highlightBlock: function () {},
};
