// MathJax 3 for pymdownx.arithmatex (generic mode): typeset only what arithmatex marked.
// MathJax itself is served with the site (docs/javascripts/mathjax, Apache-2.0): no network.
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"]],
    displayMath: [["\\[", "\\]"]],
    processEscapes: true,
    processEnvironments: true
  },
  options: {
    ignoreHtmlClass: ".*|",
    processHtmlClass: "arithmatex"
  }
};
