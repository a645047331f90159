package dev.motionfusion.app.ui

import dev.motionfusion.app.R
import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import android.util.TypedValue
import android.view.View
import com.google.android.material.R as MaterialR

/**
 * Each stream's rate over time as a lane of its own: the stream's name, a line of its events per
 * second per bin (scaled from 0 to the stream's highest bin, so a drop or a gap shows whatever
 * the stream's rate), and its highest rate; a time axis below. Lanes are as tall as two lines of text.
 */
class RatePlotView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    /** One lane: a stream's [name] and its rate per bin, Hz. */
    class Lane(val name: String, val ratesHz: FloatArray)

    private var lanes: List<Lane> = emptyList()
    private var binSeconds = 1.0
    private val density = resources.displayMetrics.density
    private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorOnSurface, Color.BLACK)
        textSize = TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, 13f, resources.displayMetrics)
    }
    private val axis = Paint(text).apply { color = themeColor(MaterialR.attr.colorOnSurfaceVariant, Color.GRAY); textSize = text.textSize * 0.92f }
    private val line = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorPrimary, Color.BLUE); style = Paint.Style.STROKE; strokeWidth = 1.5f * density; strokeJoin = Paint.Join.ROUND
    }
    private val track = Paint().apply { color = themeColor(MaterialR.attr.colorOutlineVariant, Color.LTGRAY); strokeWidth = density }
    private val path = Path()
    private val laneHeight get() = text.textSize * 2.4f
    private val axisHeight get() = axis.textSize * 1.8f

    /** Shows [lanes], each value a bin of [binSeconds]. */
    fun setLanes(lanes: List<Lane>, binSeconds: Double) {
        this.lanes = lanes
        this.binSeconds = binSeconds
        contentDescription = lanes.joinToString(context.getString(R.string.description_separator)) { context.getString(R.string.rate_lane_description, it.name, rate(it.ratesHz.maxOrNull() ?: 0f)) }
        requestLayout()
        invalidate()
    }

    /** Streams shown. */
    val laneCount: Int get() = lanes.size

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val h = if (lanes.isEmpty()) 0f else lanes.size * laneHeight + axisHeight
        setMeasuredDimension(MeasureSpec.getSize(widthMeasureSpec), resolveSize(h.toInt(), heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        if (lanes.isEmpty()) return
        val left = lanes.maxOf { text.measureText(it.name) } + 10 * density
        val right = width - (lanes.maxOf { text.measureText(rate(it.ratesHz.maxOrNull() ?: 0f)) } + 10 * density)
        val bins = lanes.maxOf { it.ratesHz.size }.coerceAtLeast(1)
        val binWidth = (right - left) / bins
        lanes.forEachIndexed { i, lane ->
            val top = i * laneHeight + laneHeight * 0.15f
            val bottom = (i + 1) * laneHeight - laneHeight * 0.15f
            val baseline = i * laneHeight + laneHeight / 2 + text.textSize / 3
            canvas.drawText(lane.name, 0f, baseline, text)
            canvas.drawLine(left, bottom, right, bottom, track)
            val peak = lane.ratesHz.maxOrNull() ?: 0f
            if (peak > 0f) {
                path.rewind()
                for (k in lane.ratesHz.indices) {
                    val x = left + (k + 0.5f) * binWidth
                    val y = bottom - (bottom - top) * lane.ratesHz[k] / peak
                    if (k == 0) path.moveTo(x, y) else path.lineTo(x, y)
                }
                canvas.drawPath(path, line)
            }
            canvas.drawText(rate(peak), right + 10 * density, baseline, text)
        }
        val y = lanes.size * laneHeight + axis.textSize * 1.2f
        val end = context.getString(R.string.axis_seconds, bins * binSeconds)
        canvas.drawText(context.getString(R.string.axis_seconds, 0.0), left, y, axis)
        val bin = if (binSeconds % 1.0 == 0.0) context.getString(R.string.rate_bins, binSeconds) else context.getString(R.string.rate_bins_fraction, binSeconds)
        // The bin width between the two ends where it fits beside them (not with large text on a narrow screen).
        val gap = 8 * density
        val binW = axis.measureText(bin)
        val binX = (left + right) / 2 - binW / 2
        if (binX >= left + axis.measureText(context.getString(R.string.axis_seconds, 0.0)) + gap && binX + binW <= right - axis.measureText(end) - gap) {
            canvas.drawText(bin, binX, y, axis)
        }
        canvas.drawText(end, right - axis.measureText(end), y, axis)
    }

    private fun rate(hz: Float) = context.getString(R.string.rate_hz_whole, hz)
}
