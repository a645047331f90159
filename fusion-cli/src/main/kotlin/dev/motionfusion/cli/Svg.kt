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

/**
 * A hand-written SVG figure of stacked panels sharing the time axis, with [marks] (moments
 * marked while recording) drawn as vertical lines through every panel, labelled in the first.
 */
internal class SvgFigure(private val title: String, private val tMin: Double, private val tMax: Double, private val marks: List<Mark> = emptyList()) {
    class Line(val label: String, val color: String, val data: Envelope, val wraps: Boolean)

    /** A marker at [t] (s on the figure's time axis) with its [label] (shown cut to [SHOWN_CHARS], whole in its tooltip). */
    class Mark(val t: Double, val label: String)
    class Panel(val yLabel: String, val lines: List<Line>, val yMin: Double?, val yMax: Double?, val yStep: Double?)

    private val panels = ArrayList<Panel>()

    fun panel(p: Panel) { panels += p }

    fun render(): String {
        val w = 1000.0
        val ph = 260.0
        val left = 70.0
        val right = 150.0
        val top = 40.0
        val gap = 50.0
        val h = top + panels.size * ph + (panels.size - 1) * gap + 50.0
        val sb = StringBuilder()
        svgStart(sb, w, h, left, title)
        val plotW = w - left - right
        val span = if (tMax > tMin) tMax - tMin else 1.0
        fun x(t: Double) = left + (t - tMin) / span * plotW
        for ((pi, p) in panels.withIndex()) {
            val y0 = top + pi * (ph + gap)
            val all = p.lines.flatMap { l -> l.data.points().map { it.second } }
            var yMin = p.yMin ?: (all.minOrNull() ?: 0.0)
            var yMax = p.yMax ?: (all.maxOrNull() ?: 1.0)
            if (yMax <= yMin) yMax = yMin + 1.0
            val yStep = p.yStep ?: niceStep((yMax - yMin) / 5)
            if (p.yMin == null) yMin = floor(yMin / yStep) * yStep
            if (p.yMax == null) yMax = ceil(yMax / yStep) * yStep
            fun y(v: Double) = y0 + ph - (v - yMin) / (yMax - yMin) * ph
            sb.append("""<g>""").append('\n')
            sb.append("""<rect x="${svgNum(left)}" y="${svgNum(y0)}" width="${svgNum(plotW)}" height="${svgNum(ph)}" fill="none" stroke="#444"/>""").append('\n')
            var v = yMin
            while (v <= yMax + 1e-9) {
                sb.append("""<line x1="${svgNum(left)}" x2="${svgNum(left + plotW)}" y1="${svgNum(y(v))}" y2="${svgNum(y(v))}" stroke="#ddd"/>""")
                sb.append("""<text x="${svgNum(left - 6)}" y="${svgNum(y(v) + 4)}" text-anchor="end">${num(v)}</text>""").append('\n')
                v += yStep
            }
            val tStep = niceStep(span / 8)
            var t = ceil(tMin / tStep) * tStep
            while (t <= tMax + 1e-9) {
                sb.append("""<line x1="${svgNum(x(t))}" x2="${svgNum(x(t))}" y1="${svgNum(y0)}" y2="${svgNum(y0 + ph)}" stroke="#eee"/>""")
                sb.append("""<text x="${svgNum(x(t))}" y="${svgNum(y0 + ph + 16)}" text-anchor="middle">${num(t)}</text>""").append('\n')
                t += tStep
            }
            sb.append("""<text transform="translate(18 ${svgNum(y0 + ph / 2)}) rotate(-90)" text-anchor="middle">${svgEsc(p.yLabel)}</text>""").append('\n')
            for ((li, l) in p.lines.withIndex()) {
                val pts = l.data.points()
                val path = StringBuilder()
                var prev = Double.NaN
                for ((tt, vv) in pts) {
                    val cmd = if (prev.isNaN() || (l.wraps && abs(vv - prev) > 180.0)) "M" else "L"
                    path.append(cmd).append(svgNum(x(tt))).append(',').append(svgNum(y(vv.coerceIn(yMin, yMax)))).append(' ')
                    prev = vv
                }
                sb.append("""<path d="${path.toString().trim()}" fill="none" stroke="${l.color}" stroke-width="1.2"/>""").append('\n')
                val ly = y0 + 16 + li * 18
                svgLegend(sb, left + plotW + 12, ly, l.color, "", l.label)
            }
            for (m in marks) {
                if (m.t < tMin || m.t > tMax) continue
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
        sb.append("""<text x="${svgNum(left + plotW / 2)}" y="${svgNum(h - 10)}" text-anchor="middle">time (s)</text>""").append('\n')
        sb.append("</svg>\n")
        return sb.toString()
    }

    private fun niceStep(raw: Double): Double {
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

    private companion object {
        const val MARK_COLOR = "#7b2cbf"
        const val SHOWN_CHARS = 40
    }

    private fun num(v: Double): String = if (abs(v - Math.rint(v)) < 1e-9) String.format(Locale.ROOT, "%d", Math.rint(v).toLong()) else String.format(Locale.ROOT, "%.2f", v).trimEnd('0')
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

/**
 * A hand-written SVG figure of panels with logarithmic x and y axes (decades gridded), each
 * holding curves drawn as lines and points and straight lines given by two end points.
 */
internal class LogLogFigure(private val title: String, private val xLabel: String) {
    class Curve(val label: String, val color: String, val x: DoubleArray, val y: DoubleArray, val dashed: Boolean = false)
    class Panel(val yLabel: String, val curves: List<Curve>)

    private val panels = ArrayList<Panel>()

    fun panel(p: Panel) { panels += p }

    fun render(): String {
        val w = 1000.0
        val ph = 360.0
        val left = 80.0
        val right = 230.0
        val top = 40.0
        val gap = 60.0
        val h = top + panels.size * ph + (panels.size - 1) * gap + 50.0
        val plotW = w - left - right
        val sb = StringBuilder()
        svgStart(sb, w, h, left, title)
        fun finite(c: Curve) = c.x.indices.filter { c.x[it] > 0 && c.y[it] > 0 && c.x[it].isFinite() && c.y[it].isFinite() }
        val xs = panels.flatMap { p -> p.curves.filter { !it.dashed }.flatMap { c -> finite(c).map { c.x[it] } } }
        val xMin = floor(log10(xs.minOrNull() ?: 0.1))
        val xMax = ceil(log10(xs.maxOrNull() ?: 10.0)).coerceAtLeast(xMin + 1)
        fun x(v: Double) = left + (log10(v) - xMin) / (xMax - xMin) * plotW
        for ((pi, p) in panels.withIndex()) {
            val y0 = top + pi * (ph + gap)
            val ys = p.curves.filter { !it.dashed }.flatMap { c -> finite(c).map { c.y[it] } }
            val yMin = floor(log10(ys.minOrNull() ?: 0.1))
            val yMax = ceil(log10(ys.maxOrNull() ?: 10.0)).coerceAtLeast(yMin + 1)
            fun y(v: Double) = y0 + ph - (log10(v) - yMin) / (yMax - yMin) * ph
            sb.append("<g>\n")
            sb.append("""<rect x="${svgNum(left)}" y="${svgNum(y0)}" width="${svgNum(plotW)}" height="${svgNum(ph)}" fill="none" stroke="#444"/>""").append('\n')
            for (e in yMin.toInt()..yMax.toInt()) {
                val yy = y(10.0.pow(e))
                sb.append("""<line x1="${svgNum(left)}" x2="${svgNum(left + plotW)}" y1="${svgNum(yy)}" y2="${svgNum(yy)}" stroke="#ddd"/>""")
                sb.append("""<text x="${svgNum(left - 6)}" y="${svgNum(yy + 4)}" text-anchor="end">1e$e</text>""").append('\n')
            }
            for (e in xMin.toInt()..xMax.toInt()) {
                val xx = x(10.0.pow(e))
                sb.append("""<line x1="${svgNum(xx)}" x2="${svgNum(xx)}" y1="${svgNum(y0)}" y2="${svgNum(y0 + ph)}" stroke="#eee"/>""")
                sb.append("""<text x="${svgNum(xx)}" y="${svgNum(y0 + ph + 16)}" text-anchor="middle">1e$e</text>""").append('\n')
            }
            sb.append("""<text transform="translate(18 ${svgNum(y0 + ph / 2)}) rotate(-90)" text-anchor="middle">${svgEsc(p.yLabel)}</text>""").append('\n')
            sb.append("""<clipPath id="c$pi"><rect x="${svgNum(left)}" y="${svgNum(y0)}" width="${svgNum(plotW)}" height="${svgNum(ph)}"/></clipPath>""").append('\n')
            for ((ci, c) in p.curves.withIndex()) {
                val path = finite(c).joinToString(" ") { i -> "${if (i == finite(c).first()) "M" else "L"}${svgNum(x(c.x[i]))},${svgNum(y(c.y[i]))}" }
                val dash = if (c.dashed) """ stroke-dasharray="6 4"""" else ""
                sb.append("""<path d="$path" fill="none" stroke="${c.color}" stroke-width="${if (c.dashed) "1" else "1.5"}"$dash clip-path="url(#c$pi)"/>""").append('\n')
                val ly = y0 + 16 + ci * 18
                svgLegend(sb, left + plotW + 12, ly, c.color, dash, c.label)
            }
            sb.append("</g>\n")
        }
        sb.append("""<text x="${svgNum(left + plotW / 2)}" y="${svgNum(h - 10)}" text-anchor="middle">${svgEsc(xLabel)}</text>""").append('\n')
        sb.append("</svg>\n")
        return sb.toString()
    }
}
