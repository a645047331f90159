package dev.motionfusion.app.ui

import dev.motionfusion.app.R
import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Paint
import android.util.AttributeSet
import android.util.TypedValue
import android.view.View
import com.google.android.material.R as MaterialR
import kotlin.math.max

/**
 * The achieved rate of each stream as a horizontal bar: the stream's name, a bar scaled to the
 * fastest stream, and the rate in Hz. One row per stream, as tall as its text.
 */
class RateBarsView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    /** One bar: a stream's [name] and its achieved [rateHz]. */
    data class Bar(val name: String, val rateHz: Double)

    private var bars: List<Bar> = emptyList()
    private val density = resources.displayMetrics.density
    private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorOnSurface, Color.BLACK)
        textSize = TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, 13f, resources.displayMetrics)
    }
    private val fill = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorPrimary, Color.BLUE) }
    private val track = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorSurfaceVariant, Color.LTGRAY) }
    private val rowHeight get() = text.textSize * 2f

    fun setBars(bars: List<Bar>) {
        this.bars = bars
        contentDescription = bars.joinToString(context.getString(R.string.description_separator)) { context.getString(R.string.rate_bar_description, it.name, rate(it.rateHz)) }
        requestLayout()
        invalidate()
    }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        setMeasuredDimension(MeasureSpec.getSize(widthMeasureSpec), resolveSize((bars.size * rowHeight).toInt(), heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        if (bars.isEmpty()) return
        val nameWidth = bars.maxOf { text.measureText(it.name) } + 10 * density
        val valueWidth = bars.maxOf { text.measureText(rate(it.rateHz)) } + 10 * density
        val left = nameWidth
        val right = width - valueWidth
        val fastest = max(bars.maxOf { it.rateHz }, 1e-9)
        val radius = 3 * density
        bars.forEachIndexed { i, b ->
            val top = i * rowHeight
            val baseline = top + rowHeight / 2 + text.textSize / 3
            canvas.drawText(b.name, 0f, baseline, text)
            val barTop = top + rowHeight * 0.3f
            val barBottom = top + rowHeight * 0.7f
            canvas.drawRoundRect(left, barTop, right, barBottom, radius, radius, track)
            val end = left + ((right - left) * (b.rateHz / fastest)).toFloat().coerceAtLeast(0f)
            if (b.rateHz > 0) canvas.drawRoundRect(left, barTop, end, barBottom, radius, radius, fill)
            canvas.drawText(rate(b.rateHz), right + 10 * density, baseline, text)
        }
    }

    private fun rate(hz: Double) = context.getString(R.string.rate_hz, hz)
}
