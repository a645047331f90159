package dev.motionfusion.cli

import java.util.Locale
import kotlin.math.abs
import kotlin.math.ceil
import kotlin.math.floor
import kotlin.math.log10
import kotlin.math.pow

/**
 * A time series reduced to at most [CAP] buckets of equal width, each keeping its minimum and
 * maximum in the order they occurred: constant memory for any length, and the envelope of the
 * curve is kept (no spike disappears), as a plot at ~1000 pixels needs.
 */
internal class Envelope {
    private var t0 = Double.NaN
    private var width = 0.01
    private val lo = DoubleArray(CAP) { Double.NaN }
    private val hi = DoubleArray(CAP) { Double.NaN }
    private val loFirst = BooleanArray(CAP)
    var lastT = Double.NaN
        private set

    fun add(t: Double, v: Double) {
        if (!t.isFinite() || !v.isFinite()) return
        if (t0.isNaN()) t0 = t
        lastT = t
        var i = floor((t - t0) / width).toInt()
        if (i < 0) return
        while (i >= CAP) {
            merge()
            i = floor((t - t0) / width).toInt()
        }
        if (lo[i].isNaN()) {
            lo[i] = v; hi[i] = v; loFirst[i] = true
        } else {
            if (v < lo[i]) { lo[i] = v; loFirst[i] = false }
            if (v > hi[i]) { hi[i] = v; loFirst[i] = true }
        }
    }

    private fun merge() {
        for (k in 0 until CAP / 2) {
            val a = 2 * k
            val b = a + 1
            val l = minOf2(lo[a], lo[b])
            val h = maxOf2(hi[a], hi[b])
            val lf = when {
                lo[a].isNaN() -> loFirst[b]
                lo[b].isNaN() -> loFirst[a]
                else -> l == lo[a] // the minimum came from the earlier half
            }
            lo[k] = l; hi[k] = h; loFirst[k] = lf
        }
        for (k in CAP / 2 until CAP) { lo[k] = Double.NaN; hi[k] = Double.NaN }
        width *= 2
    }

    private fun minOf2(a: Double, b: Double) = if (a.isNaN()) b else if (b.isNaN()) a else minOf(a, b)
    private fun maxOf2(a: Double, b: Double) = if (a.isNaN()) b else if (b.isNaN()) a else maxOf(a, b)

    /** The points (t, v) in time order: per bucket min and max (one point when equal). */
    /** The envelope as a curve of [SvgFigure]. */
    fun curve(label: String, color: String, wraps: Boolean): SvgFigure.Curve {
        val p = points()
        return SvgFigure.Curve(label, color, DoubleArray(p.size) { p[it].first }, DoubleArray(p.size) { p[it].second }, wraps = wraps)
    }

    fun points(): List<Pair<Double, Double>> {
        val out = ArrayList<Pair<Double, Double>>()
        for (i in 0 until CAP) {
            if (lo[i].isNaN()) continue
            val ta = t0 + (i + 0.25) * width
            val tb = t0 + (i + 0.75) * width
            if (lo[i] == hi[i]) out += (t0 + (i + 0.5) * width) to lo[i]
            else if (loFirst[i]) { out += ta to lo[i]; out += tb to hi[i] } else { out += ta to hi[i]; out += tb to lo[i] }
        }
        return out
    }

    val isEmpty: Boolean get() = t0.isNaN()

    companion object {
        const val CAP = 1024
    }
}

/** How values map onto an axis: [Linear] with round steps, or [Log] in decades. */
internal sealed class Scale {
    /** The axis's [min] and [max] for the values [v] (fixed ends where given), and its ticks with their labels. */
    abstract fun range(v: List<Double>, min: Double?, max: Double?, step: Double?): Axis

    class Axis(val min: Double, val max: Double, val ticks: List<Pair<Double, String>>, val position: (Double) -> Double)

    object Linear : Scale() {
        override fun range(v: List<Double>, min: Double?, max: Double?, step: Double?): Axis {
            var lo = min ?: (v.minOrNull() ?: 0.0)
            var hi = max ?: (v.maxOrNull() ?: 1.0)
            if (hi <= lo) hi = lo + 1.0
            val s = step ?: niceStep((hi - lo) / 5)
            if (min == null) lo = floor(lo / s) * s
            if (max == null) hi = ceil(hi / s) * s
            val ticks = ArrayList<Pair<Double, String>>()
            var t = ceil(lo / s - 1e-9) * s
            while (t <= hi + 1e-9) {
                ticks += t to num(t)
                t += s
            }
            return Axis(lo, hi, ticks) { it }
        }
    }

    object Log : Scale() {
        override fun range(v: List<Double>, min: Double?, max: Double?, step: Double?): Axis {
            val lo = floor(log10(v.filter { it > 0 }.minOrNull() ?: 0.1))
            val hi = ceil(log10(v.filter { it > 0 }.maxOrNull() ?: 10.0)).coerceAtLeast(lo + 1)
            return Axis(lo, hi, (lo.toInt()..hi.toInt()).map { e -> e.toDouble() to "1e$e" }) { log10(it) }
        }
    }

    companion object {
        fun niceStep(raw: Double): Double {
            if (!(raw > 0)) return 1.0
            val e = 10.0.pow(floor(log10(raw)))
            val m = raw / e
            return e * when {
                m <= 1.0 -> 1.0
                m <= 2.0 -> 2.0
                m <= 5.0 -> 5.0
                else -> 10.0
            }
        }

        fun num(v: Double): String = if (abs(v - Math.rint(v)) < 1e-9) String.format(Locale.ROOT, "%d", Math.rint(v).toLong()) else String.format(Locale.ROOT, "%.2f", v).trimEnd('0')
    }
}

/**
 * A hand-written SVG figure: panels stacked one above the other sharing the x axis ([xScale],
 * [xLabel]; [xMin]/[xMax] fixed, or from the data), each with its own y axis, curves and legend;
 * [marks] (moments marked while recording) as vertical lines through every panel, labelled in the
 * first. One renderer for `fusion plot` (time series) and `fusion allan --plot` (log–log).
 */
internal class SvgFigure(
    private val title: String,
    private val xLabel: String,
    private val xScale: Scale = Scale.Linear,
    private val xMin: Double? = null,
    private val xMax: Double? = null,
    private val marks: List<Mark> = emptyList(),
    private val panelHeight: Double = 260.0,
    private val legendWidth: Double = 150.0,
) {
    /**
     * A curve: [x], [y] (points that do not fit the scale, such as ≤ 0 on a log axis or not
     * finite, are left out), [dashed] lines thinner; [wraps]: a jump over 180 starts a new stroke
     * (angles). [guide]: a line drawn for reference that does not set the axes' ranges.
     */
    class Curve(val label: String, val color: String, val x: DoubleArray, val y: DoubleArray, val dashed: Boolean = false, val wraps: Boolean = false, val guide: Boolean = false)

    /** A marker at [t] (on the x axis) with its [label] (shown cut to [SHOWN_CHARS], whole in its tooltip). */
    class Mark(val t: Double, val label: String)

    /** A panel: its y axis ([yScale], fixed ends and step where given) and its curves. */
    class Panel(val yLabel: String, val curves: List<Curve>, val yMin: Double? = null, val yMax: Double? = null, val yStep: Double? = null, val yScale: Scale = Scale.Linear)

    private val panels = ArrayList<Panel>()

    fun panel(p: Panel) { panels += p }

    private fun fits(scale: Scale, v: Double) = v.isFinite() && (scale != Scale.Log || v > 0)

    fun render(): String {
        val w = 1000.0
        val ph = panelHeight
        val left = 70.0
        val top = 40.0
        val gap = 50.0
        val h = top + panels.size * ph + (panels.size - 1) * gap + 50.0
        val plotW = w - left - legendWidth
        val sb = StringBuilder()
        svgStart(sb, w, h, left, title)
        val xs = panels.flatMap { p -> p.curves.filter { !it.guide }.flatMap { c -> c.x.filter { fits(xScale, it) } } }
        val xAxis = xScale.range(xs, xMin, xMax, null).let { a ->
            // A time axis keeps its data's ends and takes about eight round steps between them.
            if (xScale == Scale.Linear) {
                val lo = xMin ?: (xs.minOrNull() ?: 0.0)
                val hi = (xMax ?: (xs.maxOrNull() ?: 1.0)).let { if (it > lo) it else lo + 1.0 }
                Scale.Linear.range(emptyList(), lo, hi, Scale.niceStep((hi - lo) / 8))
            } else {
                a
            }
        }
        fun x(v: Double) = left + (xAxis.position(v) - xAxis.min) / (xAxis.max - xAxis.min) * plotW
        for ((pi, p) in panels.withIndex()) {
            val y0 = top + pi * (ph + gap)
            val yAxis = p.yScale.range(p.curves.filter { !it.guide }.flatMap { c -> c.y.filter { fits(p.yScale, it) } }, p.yMin, p.yMax, p.yStep)
            fun y(v: Double) = y0 + ph - (p.yScale.let { yAxis.position(v) } - yAxis.min) / (yAxis.max - yAxis.min) * ph
            sb.append("<g>\n")
            sb.append("""<rect x="${svgNum(left)}" y="${svgNum(y0)}" width="${svgNum(plotW)}" height="${svgNum(ph)}" fill="none" stroke="#444"/>""").append('\n')
            for ((v, label) in yAxis.ticks) {
                val yy = y0 + ph - (v - yAxis.min) / (yAxis.max - yAxis.min) * ph
                sb.append("""<line x1="${svgNum(left)}" x2="${svgNum(left + plotW)}" y1="${svgNum(yy)}" y2="${svgNum(yy)}" stroke="#ddd"/>""")
                sb.append("""<text x="${svgNum(left - 6)}" y="${svgNum(yy + 4)}" text-anchor="end">$label</text>""").append('\n')
            }
            for ((v, label) in xAxis.ticks) {
                val xx = left + (v - xAxis.min) / (xAxis.max - xAxis.min) * plotW
                sb.append("""<line x1="${svgNum(xx)}" x2="${svgNum(xx)}" y1="${svgNum(y0)}" y2="${svgNum(y0 + ph)}" stroke="#eee"/>""")
                sb.append("""<text x="${svgNum(xx)}" y="${svgNum(y0 + ph + 16)}" text-anchor="middle">$label</text>""").append('\n')
            }
            sb.append("""<text transform="translate(18 ${svgNum(y0 + ph / 2)}) rotate(-90)" text-anchor="middle">${svgEsc(p.yLabel)}</text>""").append('\n')
            sb.append("""<clipPath id="c$pi"><rect x="${svgNum(left)}" y="${svgNum(y0)}" width="${svgNum(plotW)}" height="${svgNum(ph)}"/></clipPath>""").append('\n')
            for ((ci, c) in p.curves.withIndex()) {
                val path = StringBuilder()
                var prev = Double.NaN
                for (i in c.x.indices) {
                    if (!fits(xScale, c.x[i]) || !fits(p.yScale, c.y[i])) continue
                    val cmd = if (prev.isNaN() || (c.wraps && abs(c.y[i] - prev) > 180.0)) "M" else "L"
                    path.append(cmd).append(svgNum(x(c.x[i]))).append(',').append(svgNum(y(c.y[i]))).append(' ')
                    prev = c.y[i]
                }
                val dash = if (c.dashed) """ stroke-dasharray="6 4"""" else ""
                sb.append("""<path d="${path.toString().trim()}" fill="none" stroke="${c.color}" stroke-width="${if (c.dashed) "1" else "1.2"}"$dash clip-path="url(#c$pi)"/>""").append('\n')
                svgLegend(sb, left + plotW + 12, y0 + 16 + ci * 18, c.color, dash, c.label)
            }
            for (m in marks) {
                if (m.t < xAxis.min || m.t > xAxis.max) continue
                val mx = svgNum(x(m.t))
                sb.append("""<g class="marker"><title>${svgEsc(m.label)}</title>""")
                sb.append("""<line x1="$mx" x2="$mx" y1="${svgNum(y0)}" y2="${svgNum(y0 + ph)}" stroke="$MARK_COLOR" stroke-width="1" stroke-dasharray="4 3"/>""")
                if (pi == 0) {
                    val shown = if (m.label.length > SHOWN_CHARS) m.label.take(SHOWN_CHARS - 1) + "…" else m.label
                    sb.append("""<text transform="translate(${svgNum(x(m.t) + 4)} ${svgNum(y0 + 6)}) rotate(90)" fill="$MARK_COLOR" font-size="11">${svgEsc(shown)}</text>""")
                }
                sb.append("</g>\n")
            }
            sb.append("</g>\n")
        }
        sb.append("""<text x="${svgNum(left + plotW / 2)}" y="${svgNum(h - 10)}" text-anchor="middle">${svgEsc(xLabel)}</text>""").append('\n')
        sb.append("</svg>\n")
        return sb.toString()
    }

    private companion object {
        const val MARK_COLOR = "#7b2cbf"
        const val SHOWN_CHARS = 40
    }
}

/** An SVG coordinate, one decimal. */
internal fun svgNum(v: Double): String = String.format(Locale.ROOT, "%.1f", v)

/** Opens an SVG document of [w] × [h] with a white background and [title] at [left]. */
internal fun svgStart(sb: StringBuilder, w: Double, h: Double, left: Double, title: String) {
    sb.append("""<svg xmlns="http://www.w3.org/2000/svg" width="${svgNum(w)}" height="${svgNum(h)}" viewBox="0 0 ${svgNum(w)} ${svgNum(h)}" font-family="sans-serif" font-size="12">""").append('\n')
    sb.append("""<rect width="100%" height="100%" fill="white"/>""").append('\n')
    sb.append("""<text x="${svgNum(left)}" y="22" font-size="15" font-weight="bold">${svgEsc(title)}</text>""").append('\n')
}

/** One legend entry at ([x], [y]): a short line in [color] ([dash]: extra attributes) and [label]. */
internal fun svgLegend(sb: StringBuilder, x: Double, y: Double, color: String, dash: String, label: String) {
    sb.append("""<line x1="${svgNum(x)}" x2="${svgNum(x + 20)}" y1="${svgNum(y - 4)}" y2="${svgNum(y - 4)}" stroke="$color" stroke-width="2"$dash/>""")
    sb.append("""<text x="${svgNum(x + 26)}" y="${svgNum(y)}">${svgEsc(label)}</text>""").append('\n')
}

/** Text escaped for SVG. */
internal fun svgEsc(s: String): String = s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
