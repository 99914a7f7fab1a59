// Small-screen menu toggle. The site works without JavaScript: the menu is only hidden on phones.
(function () {
  var button = document.querySelector(".menu-toggle");
  var nav = document.getElementById("nav");
  if (!button || !nav) return;
  button.addEventListener("click", function () {
    var shown = nav.classList.toggle("shown");
    button.setAttribute("aria-expanded", shown ? "true" : "false");
  });
})();
