package dev.motionfusion.app.sessions

import android.content.Context
import android.graphics.Canvas
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import android.util.TypedValue
import android.view.View
import dev.motionfusion.app.R

/**
 * Azimuth, pitch and roll (degrees, −180..180) against time (s): three lines over a grid, with
 * a legend. Wrap-arounds of azimuth and roll (±180°) break the line instead of drawing a
 * vertical stroke across the plot.
 */
internal class AnglePlotView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    private var series: AngleSeries? = null
    private val dp = resources.displayMetrics.density
    private val textPx = TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, 12f, resources.displayMetrics)
    private val grid = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = context.getColor(R.color.plot_grid); strokeWidth = 1 * dp }
    private val label = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = context.getColor(R.color.plot_label); textSize = textPx }
    private val lines = listOf(R.color.plot_azimuth, R.color.plot_pitch, R.color.plot_roll).map { c ->
        Paint(Paint.ANTI_ALIAS_FLAG).apply { color = context.getColor(c); style = Paint.Style.STROKE; strokeWidth = 1.5f * dp }
    }
    private val names = listOf(R.string.plot_azimuth, R.string.plot_pitch, R.string.plot_roll).map(context::getString)
    private val path = Path()

    fun setSeries(s: AngleSeries?) {
        series = s
        contentDescription = if (s == null || s.size == 0) context.getString(R.string.session_plot_empty) else context.getString(R.string.session_plot_title)
        invalidate()
    }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val w = MeasureSpec.getSize(widthMeasureSpec)
        setMeasuredDimension(w, resolveSize((240 * dp).toInt(), heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        val left = 40 * dp
        val top = textPx * 2
        val right = width - 8 * dp
        val bottom = height - textPx * 1.8f
        val plotH = bottom - top
        fun yOf(deg: Float) = top + (180f - deg) / 360f * plotH
        for (deg in -180..180 step 90) {
            val y = yOf(deg.toFloat())
            canvas.drawLine(left, y, right, y, grid)
            canvas.drawText("$deg°", 2 * dp, y + textPx / 3, label)
        }
        // Legend.
        var lx = left
        for (i in 0..2) {
            canvas.drawLine(lx, textPx * 0.7f, lx + 16 * dp, textPx * 0.7f, lines[i])
            canvas.drawText(names[i], lx + 20 * dp, textPx, label)
            lx += 20 * dp + label.measureText(names[i]) + 16 * dp
        }
        val s = series ?: return
        if (s.size == 0) {
            canvas.drawText(context.getString(R.string.session_plot_empty), left, top + plotH / 2, label)
            return
        }
        val t0 = s.timeS[0]
        val span = (s.timeS[s.size - 1] - t0).coerceAtLeast(1e-3f)
        fun xOf(t: Float) = left + (t - t0) / span * (right - left)
        canvas.drawText("0 s", left, height - 2 * dp, label)
        val end = "%.1f s".format(java.util.Locale.ROOT, span)
        canvas.drawText(end, right - label.measureText(end), height - 2 * dp, label)
        val values = arrayOf(s.azimuthDeg, s.pitchDeg, s.rollDeg)
        for (k in 0..2) {
            val v = values[k]
            path.reset()
            path.moveTo(xOf(s.timeS[0]), yOf(v[0]))
            for (i in 1 until s.size) {
                val x = xOf(s.timeS[i])
                val y = yOf(v[i])
                if (kotlin.math.abs(v[i] - v[i - 1]) > 180f) path.moveTo(x, y) else path.lineTo(x, y)
            }
            canvas.drawPath(path, lines[k])
        }
    }
}
