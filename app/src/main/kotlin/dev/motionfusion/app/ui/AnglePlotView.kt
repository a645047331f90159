package dev.motionfusion.app.ui

import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.DashPathEffect
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import android.util.TypedValue
import android.view.View
import com.google.android.material.R as MaterialR
import dev.motionfusion.app.R
import java.util.Locale
import kotlin.math.abs

/** A labelled instant on a plot: [timestampNs] on the plotted samples' clock, [text] shown beside its line. */
data class PlotMarker(val timestampNs: Long, val text: String)

/**
 * The one plot of three angles (degrees) against time, for the live screen and a session's
 * detail: yaw or azimuth (0..360 shown as −180..180), pitch and roll on a shared −180..180° axis,
 * grid lines every 90°, a legend, and markers as labelled vertical lines. A line is not drawn
 * across a wrap-around (a jump of more than 180° between points).
 *
 * Live ([append]): the x axis covers the last [AngleTrace.windowSeconds] of sample time ending at
 * the newest sample, whatever the rate points arrive at, so a 120 Hz display shows 10 s as a 60 Hz
 * one does. A second set of angles, the "ghost" (the phone's own rotation vector), is drawn dashed
 * in the same colours.
 * Whole series ([showSeries]): the x axis spans the series, in seconds from its first point.
 */
/**
 * The points an [AnglePlotView] draws: timestamps (ns) and six angle series (yaw, pitch, roll and
 * the ghost's, degrees, yaw as −180..180), either a live window ([append]) or a whole series
 * ([showSeries]). Separate from the view so that a ViewModel can own the live history and a new
 * view after a configuration change draws the same 10 s.
 *
 * Live: the x axis covers the last [windowSeconds] of sample time ending at the newest sample,
 * whatever the rate points arrive at: points are kept by timestamp, older ones dropped, and the
 * buffer grows (rarely, amortised) when a window holds more points than it has room for. Main thread only.
 */
class AngleTrace(
    /** The live window, seconds of sample time. */
    var windowSeconds: Double = 10.0,
) {
    private var capacity = 1024
    internal var times = LongArray(capacity)
        private set
    internal var values = Array(6) { FloatArray(capacity) }
        private set
    internal var head = 0
        private set

    /** Points kept now (live: those within the window and one before it). */
    var size = 0
        private set

    /** True while the trace is a live window, false for a whole series. */
    var live = true
        private set

    /** True once a point had the ghost's angles. */
    var hasGhost = false
        private set

    /** Timestamp of the newest point, ns (Long.MIN_VALUE when empty). */
    val newestNs: Long get() = if (size == 0) Long.MIN_VALUE else times[index(size - 1)]

    /** Sample time from the oldest point kept to the newest, seconds. */
    val spanSeconds: Double get() = if (size < 2) 0.0 else (times[index(size - 1)] - times[index(0)]) / 1e9

    /**
     * Appends angles at [timeNs] (the samples' clock, ns) with the ghost's angles (NaN when there
     * is none); a point not later than the newest is ignored (the same state drawn twice). Points
     * older than the window scroll off.
     */
    fun append(timeNs: Long, yawDeg: Double, pitchDeg: Double, rollDeg: Double, ghostYawDeg: Double = Double.NaN, ghostPitchDeg: Double = Double.NaN, ghostRollDeg: Double = Double.NaN) {
        if (!live) clear()
        if (size > 0 && timeNs <= newestNs) return
        val window = (windowSeconds * 1e9).toLong()
        // Drop what the window no longer shows, but keep one point before it so the line reaches the edge.
        while (size > 1 && timeNs - times[index(1)] > window) {
            head = (head + 1) % capacity
            size--
        }
        if (size == capacity) grow()
        val i = (head + size) % capacity
        times[i] = timeNs
        values[0][i] = signed(yawDeg)
        values[1][i] = pitchDeg.toFloat()
        values[2][i] = rollDeg.toFloat()
        values[3][i] = signed(ghostYawDeg)
        values[4][i] = ghostPitchDeg.toFloat()
        values[5][i] = ghostRollDeg.toFloat()
        if (!ghostYawDeg.isNaN()) hasGhost = true
        size++
    }

    /** Replaces the points by a whole series: [timeS] seconds after [originNs], angles in degrees. */
    fun showSeries(originNs: Long, timeS: FloatArray, yawDeg: FloatArray, pitchDeg: FloatArray, rollDeg: FloatArray) {
        clear()
        live = false
        while (capacity < timeS.size) grow()
        for (k in timeS.indices) {
            times[k] = originNs + (timeS[k] * 1e9).toLong()
            values[0][k] = signed(yawDeg[k].toDouble()); values[1][k] = pitchDeg[k]; values[2][k] = rollDeg[k]
            values[3][k] = Float.NaN; values[4][k] = Float.NaN; values[5][k] = Float.NaN
        }
        size = timeS.size
    }

    fun clear() {
        size = 0; head = 0; live = true; hasGhost = false
    }

    internal fun index(k: Int) = (head + k) % capacity

    private fun signed(yaw: Double): Float = (if (yaw > 180.0) yaw - 360.0 else yaw).toFloat()

    /** Twice the room, the oldest point first. */
    private fun grow() {
        val n = capacity * 2
        val t = LongArray(n)
        val v = Array(6) { FloatArray(n) }
        for (k in 0 until size) {
            val i = index(k)
            t[k] = times[i]
            for (s in 0 until 6) v[s][k] = values[s][i]
        }
        times = t; values = v; capacity = n; head = 0
    }
}

class AnglePlotView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    /**
     * The points drawn. The live screen sets the one its ViewModel owns, so the history survives
     * a configuration change; otherwise the view has its own.
     */
    var trace: AngleTrace = AngleTrace()
        set(value) { field = value; invalidate() }

    private var markers: List<PlotMarker> = emptyList()

    private val density = resources.displayMetrics.density
    private val textPx = TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, 12f, resources.displayMetrics)
    private val colours = intArrayOf(context.getColor(R.color.plot_azimuth), context.getColor(R.color.plot_pitch), context.getColor(R.color.plot_roll))
    private val lines = Array(3) { i ->
        Paint(Paint.ANTI_ALIAS_FLAG).apply {
            color = colours[i]; style = Paint.Style.STROKE; strokeWidth = 2f * density; strokeJoin = Paint.Join.ROUND
        }
    }
    private val ghostLines = Array(3) { i ->
        Paint(lines[i]).apply {
            strokeWidth = 1.5f * density; alpha = 0xA0
            pathEffect = DashPathEffect(floatArrayOf(5f * density, 4f * density), 0f)
        }
    }
    private val grid = Paint().apply { color = themeColor(MaterialR.attr.colorOutlineVariant, Color.LTGRAY); strokeWidth = density }
    private val label = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorOnSurfaceVariant, Color.GRAY); textSize = textPx
    }
    private val markerLine = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorTertiary, Color.MAGENTA); strokeWidth = 1.5f * density
    }
    private val markerText = Paint(label).apply { color = markerLine.color }
    private val names = arrayOf(context.getString(R.string.azimuth), context.getString(R.string.pitch), context.getString(R.string.roll))
    private val ghostName = context.getString(R.string.plot_ghost)
    private val path = Path()

    /** Shown in the middle while there is nothing to plot; null for nothing. */
    var emptyText: String? = null
        set(value) { field = value; invalidate() }

    /** The first angle's name in the legend: azimuth (Android) or yaw (aerospace). */
    fun setYawName(name: String) {
        if (names[0] == name) return
        names[0] = name
        invalidate()
    }

    /** The colour of series [i] (0 yaw, 1 pitch, 2 roll). */
    fun colour(i: Int): Int = colours[i]

    /** Points kept now (live: those within the window and one before it). */
    val pointCount: Int get() = trace.size

    /** Sample time from the oldest point kept to the newest, seconds. */
    val spanSeconds: Double get() = trace.spanSeconds

    /** Appends a live point to [trace] ([AngleTrace.append]) and redraws. */
    fun append(timeNs: Long, yawDeg: Double, pitchDeg: Double, rollDeg: Double, ghostYawDeg: Double = Double.NaN, ghostPitchDeg: Double = Double.NaN, ghostRollDeg: Double = Double.NaN) {
        trace.append(timeNs, yawDeg, pitchDeg, rollDeg, ghostYawDeg, ghostPitchDeg, ghostRollDeg)
        invalidate()
    }

    /**
     * Shows a whole series: [timeS] seconds after [originNs] (the clock of [markers]), with its
     * angles in degrees; replaces what the plot held.
     */
    fun showSeries(originNs: Long, timeS: FloatArray, yawDeg: FloatArray, pitchDeg: FloatArray, rollDeg: FloatArray, markers: List<PlotMarker>) {
        trace.showSeries(originNs, timeS, yawDeg, pitchDeg, rollDeg)
        this.markers = markers
        invalidate()
    }

    /** Markers to draw (live: those inside the window). */
    fun setMarkers(markers: List<PlotMarker>) {
        if (markers == this.markers) return
        this.markers = markers
        invalidate()
    }

    fun clear() {
        trace.clear()
        markers = emptyList()
        invalidate()
    }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val w = MeasureSpec.getSize(widthMeasureSpec)
        // At least its layout's height; taller with large text, so the five angle labels of the axis never overlap.
        val wanted = maxOf(suggestedMinimumHeight.takeIf { it > 0 } ?: (200 * density).toInt(), (9.5f * textPx).toInt())
        setMeasuredDimension(w, resolveSize(wanted, heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        val left = label.measureText("-180°") + 6 * density
        val top = textPx * 2.2f
        val right = width - 8 * density
        val bottom = height - textPx * 1.8f
        val plotH = bottom - top
        fun yOf(deg: Float) = top + (180f - deg) / 360f * plotH
        for (deg in -180..180 step 90) {
            val y = yOf(deg.toFloat())
            canvas.drawLine(left, y, right, y, grid)
            canvas.drawText("$deg°", 2 * density, y + textPx / 3, label)
        }
        val trace = trace
        val size = trace.size
        val times = trace.times
        val live = trace.live
        drawLegend(canvas, left, trace.hasGhost)
        if (size == 0) {
            emptyText?.let { canvas.drawText(it, left + 8 * density, top + plotH / 2 - textPx, label) }
            return
        }
        // The x range: the live window ending at the newest point, or the whole series.
        val newest = trace.newestNs
        val start = if (live) newest - (trace.windowSeconds * 1e9).toLong() else times[trace.index(0)]
        val spanNs = (newest - start).coerceAtLeast(1_000_000L).toFloat()
        fun xOf(t: Long) = left + (t - start) / spanNs * (right - left)
        drawTimeAxis(canvas, left, right, spanNs / 1e9f, live)
        canvas.save()
        canvas.clipRect(left, 0f, right, height.toFloat())
        for (s in 0 until if (trace.hasGhost) 6 else 3) {
            val v = trace.values[s]
            path.rewind()
            var open = false
            var previous = 0f
            for (k in 0 until size) {
                val i = trace.index(k)
                val value = v[i]
                if (value.isNaN()) { open = false; continue }
                val x = xOf(times[i])
                val y = yOf(value)
                if (open && abs(value - previous) <= 180f) path.lineTo(x, y) else path.moveTo(x, y)
                open = true
                previous = value
            }
            canvas.drawPath(path, if (s < 3) lines[s] else ghostLines[s - 3])
        }
        // Where each row of labels is taken: a label that would overlap one before it goes a row lower.
        val taken = ArrayList<MutableList<ClosedFloatingPointRange<Float>>>()
        for (m in markers) {
            if (m.timestampNs < start || m.timestampNs > newest) continue
            val x = xOf(m.timestampNs)
            canvas.drawLine(x, top, x, bottom, markerLine)
            val w = markerText.measureText(m.text)
            // The label to the right of its line, or to its left near the right edge.
            val tx = if (x + 4 * density + w <= right) x + 4 * density else x - 4 * density - w
            val span = (tx - 2 * density)..(tx + w + 2 * density)
            val rows = ((bottom - top) / (1.2f * textPx)).toInt().coerceAtLeast(1)
            var row = taken.indexOfFirst { r -> r.none { it.start < span.endInclusive && span.start < it.endInclusive } }
            if (row < 0) row = if (taken.size < rows) taken.size.also { taken.add(ArrayList()) } else taken.size - 1
            taken[row] += span
            canvas.drawText(m.text, tx, top + textPx * (1 + 1.2f * row), markerText)
        }
        canvas.restore()
    }

    private fun drawLegend(canvas: Canvas, left: Float, hasGhost: Boolean) {
        var x = left
        val y = textPx * 1.1f
        for (i in 0..2) {
            canvas.drawLine(x, y - textPx / 3, x + 16 * density, y - textPx / 3, lines[i])
            canvas.drawText(names[i], x + 20 * density, y, label)
            x += 20 * density + label.measureText(names[i]) + 14 * density
        }
        if (hasGhost) {
            path.rewind()
            path.moveTo(x, y - textPx / 3)
            path.lineTo(x + 20 * density, y - textPx / 3)
            canvas.drawPath(path, ghostLines[0])
            canvas.drawText(ghostName, x + 24 * density, y, label)
        }
    }

    private fun drawTimeAxis(canvas: Canvas, left: Float, right: Float, spanS: Float, live: Boolean) {
        val y = height - 2 * density
        val first = if (live) context.getString(R.string.axis_seconds_ago, spanS) else context.getString(R.string.axis_seconds, 0f)
        val last = if (live) context.getString(R.string.plot_now) else context.getString(R.string.axis_seconds_fraction, spanS)
        canvas.drawText(first, left, y, label)
        canvas.drawText(last, right - label.measureText(last), y, label)
    }
}
