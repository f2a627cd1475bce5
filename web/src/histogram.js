// The scan's histogram beside the isovalue slider: log-scaled bars, Otsu's suggestion as a
// dashed line, the current isovalue as a solid one. A click picks the isovalue under it.

export class HistogramView {
  constructor(canvas, scan, onPick) {
    this.canvas = canvas;
    this.scan = scan;
    this.iso = scan.initial_iso;
    canvas.addEventListener('click', (event) => {
      const fraction = event.offsetX / canvas.clientWidth;
      onPick(scan.value_min + fraction * (scan.value_max - scan.value_min));
    });
  }

  setIso(iso) {
    this.iso = iso;
    this.draw();
  }

  x(value) {
    const { value_min: min, value_max: max } = this.scan;
    return max > min ? ((value - min) / (max - min)) * this.canvas.width : 0;
  }

  draw() {
    const context = this.canvas.getContext('2d');
    const { width, height } = this.canvas;
    context.clearRect(0, 0, width, height);
    const counts = this.scan.histogram;
    const top = Math.log1p(Math.max(...counts));
    context.fillStyle = '#6c7a91';
    const barWidth = width / counts.length;
    counts.forEach((count, bin) => {
      const barHeight = top > 0 ? (Math.log1p(count) / top) * (height - 4) : 0;
      context.fillRect(bin * barWidth, height - barHeight, Math.max(barWidth, 1), barHeight);
    });
    this.line(this.scan.suggested_iso, '#7ee787', [4, 3]);
    this.line(this.iso, '#ff7b72', []);
  }

  line(value, colour, dash) {
    const context = this.canvas.getContext('2d');
    context.strokeStyle = colour;
    context.setLineDash(dash);
    context.lineWidth = 2;
    context.beginPath();
    context.moveTo(this.x(value), 0);
    context.lineTo(this.x(value), this.canvas.height);
    context.stroke();
  }
}
