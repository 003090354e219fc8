// PARE viewer: the leaderboard's sorting. Each cell carries the value it sorts by (data-value; empty:
// not measured, always last); a click on a column sorts by it, a second click reverses. No framework.
(function () {
  "use strict";

  function key(row, column, numeric) {
    const text = row.cells[column].dataset.value || "";
    if (text === "") return null;
    return numeric ? parseFloat(text) : text.toLowerCase();
  }

  function sortBy(table, header, column) {
    const numeric = header.dataset.sort === "number";
    const dir = header.classList.contains("sorted") && !header.classList.contains("descending") ? -1 : 1;
    const body = table.tBodies[0];
    const rows = Array.from(body.rows);
    rows.sort((a, b) => {
      const x = key(a, column, numeric);
      const y = key(b, column, numeric);
      if (x === null || y === null) return (x === null) - (y === null);
      return dir * (x < y ? -1 : x > y ? 1 : 0);
    });
    for (const row of rows) body.appendChild(row);
    for (const other of table.tHead.rows[0].cells) other.classList.remove("sorted", "descending");
    header.classList.add("sorted");
    header.classList.toggle("descending", dir < 0);
  }

  document.addEventListener("DOMContentLoaded", () => {
    const table = document.getElementById("leaderboard");
    if (!table) return;
    Array.from(table.tHead.rows[0].cells).forEach((header, column) => {
      header.addEventListener("click", () => sortBy(table, header, column));
    });
  });
})();
