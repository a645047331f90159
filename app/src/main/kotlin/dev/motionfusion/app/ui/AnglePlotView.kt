package dev.motionfusion.app.ui

import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Paint
import android.util.AttributeSet
import android.view.View
import kotlin.math.abs

/**
 * A strip chart of three angles (degrees) over the last [windowSeconds]: yaw (0..360 shown as
 * −180..180), pitch and roll on a shared −180..180° axis with grid lines every 90°. A line is not
 * drawn across a wrap-around (a jump of more than 180° between points). Points go into a fixed
 * ring buffer: adding allocates nothing.
 */
class AnglePlotView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    var windowSeconds = 10.0
    private val capacity = 1024
    private val times = LongArray(capacity)
    private val values = Array(3) { FloatArray(capacity) }
    private var size = 0
    private var head = 0

    private val colours = intArrayOf(Color.rgb(0x4F, 0xC3, 0xF7), Color.rgb(0xAE, 0xD5, 0x81), Color.rgb(0xFF, 0x8A, 0x65))
    private val paints = Array(3) { i -> Paint(Paint.ANTI_ALIAS_FLAG).apply { color = colours[i]; strokeWidth = dp(2f) } }
    private val grid = Paint().apply { color = Color.rgb(0x37, 0x47, 0x4F); strokeWidth = dp(1f) }
    private val label = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = Color.rgb(0x9A, 0xA7, 0xB0); textSize = dp(11f) }
    private val background = Paint().apply { color = Color.rgb(0x1B, 0x21, 0x28) }

    /** The colour of series [i] (0 yaw, 1 pitch, 2 roll), for a legend. */
    fun colour(i: Int): Int = colours[i]

    /** Appends angles at [timeNs] (any monotonic clock, ns); older points than the window scroll off. */
    fun add(timeNs: Long, yawDeg: Double, pitchDeg: Double, rollDeg: Double) {
        val yaw = if (yawDeg > 180.0) yawDeg - 360.0 else yawDeg
        times[head] = timeNs
        values[0][head] = yaw.toFloat()
        values[1][head] = pitchDeg.toFloat()
        values[2][head] = rollDeg.toFloat()
        head = (head + 1) % capacity
        if (size < capacity) size++
        invalidate()
    }

    fun clear() {
        size = 0; head = 0
        invalidate()
    }

    override fun onDraw(canvas: Canvas) {
        val w = width.toFloat()
        val h = height.toFloat()
        canvas.drawRect(0f, 0f, w, h, background)
        val left = dp(34f)
        val plotW = w - left - dp(6f)
        val top = dp(6f)
        val plotH = h - 2 * top
        for (g in -2..2) {
            val y = top + plotH * (0.5f - g / 4f)
            canvas.drawLine(left, y, w, y, grid)
            canvas.drawText("${g * 90}°", dp(2f), y + dp(4f), label)
        }
        if (size < 2) return
        val newest = times[(head - 1 + capacity) % capacity]
        val span = (windowSeconds * 1e9).toLong()
        for (s in 0 until 3) {
            var px = Float.NaN
            var py = Float.NaN
            var pv = 0f
            for (k in 0 until size) {
                val i = (head - size + k + capacity) % capacity
                val age = newest - times[i]
                if (age > span) continue
                val v = values[s][i]
                val x = left + plotW * (1f - age.toFloat() / span)
                val y = top + plotH * (0.5f - v / 360f)
                if (!px.isNaN() && abs(v - pv) <= 180f) canvas.drawLine(px, py, x, y, paints[s])
                px = x; py = y; pv = v
            }
        }
    }

    private fun dp(v: Float) = v * resources.displayMetrics.density
}
