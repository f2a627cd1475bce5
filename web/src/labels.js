// A label map's labels beside the view (`vdbmesh view MAP --labels`): one checkbox per label,
// with its colour, name and value, and buttons for all or none; the count of triangles drawn.

const count = (value) => Number(value).toLocaleString('en-US');
const hex = (colour) => `#${colour.map((c) => Math.round(255 * c).toString(16).padStart(2, '0')).join('')}`;

export class LabelList {
  /// @param onChange (index, visible) => void; @param onDrawn (triangles) => void
  constructor(box, labels, onChange, onDrawn) {
    Object.assign(this, { box, labels, onChange, onDrawn });
    this.visible = labels.map(() => true);
    const list = box.querySelector('#labels');
    list.innerHTML = '';
    this.boxes = labels.map((label, index) => {
      const row = document.createElement('label');
      row.title = `label ${label.value}: ${count(label.triangles)} triangles`;
      const checkbox = Object.assign(document.createElement('input'), { type: 'checkbox', checked: true });
      checkbox.dataset.label = label.value;
      checkbox.onchange = () => this.set(index, checkbox.checked);
      const swatch = Object.assign(document.createElement('span'), { className: 'swatch' });
      swatch.style.background = hex(label.colour);
      const value = Object.assign(document.createElement('span'), { className: 'value', textContent: label.value });
      row.append(checkbox, swatch, document.createTextNode(label.name), value);
      list.append(row);
      return checkbox;
    });
    box.querySelector('#labels-all').onclick = () => this.setAll(true);
    box.querySelector('#labels-none').onclick = () => this.setAll(false);
    box.classList.remove('hidden');
    this.report();
  }

  set(index, visible) {
    this.visible[index] = visible;
    this.boxes[index].checked = visible;
    this.onChange(index, visible);
    this.report();
  }

  setAll(visible) {
    this.labels.forEach((_, index) => this.set(index, visible));
  }

  /// Triangles of the labels switched on.
  drawn() {
    return this.labels.reduce((sum, label, index) => sum + (this.visible[index] ? label.triangles : 0), 0);
  }

  report() {
    const shown = this.visible.filter(Boolean).length;
    this.box.querySelector('#labels-drawn').innerHTML =
      `${shown} of ${this.labels.length} shown, <span id="drawn-triangles">${count(this.drawn())}</span> triangles`;
    this.onDrawn(this.drawn());
  }
}
