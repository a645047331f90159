package dev.motionfusion.app.calibration

import dev.motionfusion.app.R
import android.content.Context
import android.graphics.Canvas
import android.graphics.Paint
import android.graphics.RectF
import android.text.Layout
import android.text.StaticLayout
import android.text.TextPaint
import android.util.AttributeSet
import android.view.View
import com.google.android.material.color.MaterialColors
import dev.motionfusion.core.calib.DirectionCoverage

/**
 * The directions of the field covered so far, on core's equal-area grid ([DirectionCoverage]):
 * Lambert's cylindrical equal-area map of the sphere of directions in the device frame, height
 * z (screen up at the top), longitude across (−x at the edges, +x in the middle), so every
 * cell has the same area on the map as on the sphere. A cell is filled once the field has
 * pointed into it, darker the more readings it holds.
 */
class CoverageMapView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    private var hits: List<Int> = List(DirectionCoverage.CELLS) { 0 }
    private val fill = Paint(Paint.ANTI_ALIAS_FLAG)
    private val grid = Paint(Paint.ANTI_ALIAS_FLAG).apply { style = Paint.Style.STROKE }
    private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply { textAlign = Paint.Align.CENTER }
    private val captionPaint = TextPaint(Paint.ANTI_ALIAS_FLAG)

    /** The caption under the map, wrapped to [w] (at large font sizes it is wider than the screen). */
    private fun caption(w: Int): StaticLayout {
        captionPaint.textSize = labelSize()
        val s = context.getString(R.string.calibration_map_bottom)
        return StaticLayout.Builder.obtain(s, 0, s.length, captionPaint, w.coerceAtLeast(1)).setAlignment(Layout.Alignment.ALIGN_CENTER).build()
    }

    /** Below the map: the axis ticks, then the caption. */
    private fun below(w: Int) = 1.6f * labelSize() + caption(w).height
    private val cell = RectF()

    init {
        // Read before the first readings too: an empty map.
        contentDescription = context.getString(R.string.calibration_coverage_description, 0, DirectionCoverage.CELLS)
    }

    /** Readings per cell, band-major as DirectionCoverage numbers them. */
    fun setCells(cells: List<Int>) {
        require(cells.size == DirectionCoverage.CELLS) { "expected ${DirectionCoverage.CELLS} cells" }
        if (cells == hits) return
        hits = cells
        contentDescription = context.getString(R.string.calibration_coverage_description, cells.count { it > 0 }, DirectionCoverage.CELLS)
        invalidate()
    }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        // Twice as wide as high (the map of a sphere, 2π by 2 in longitude and z), plus the labels.
        val w = MeasureSpec.getSize(widthMeasureSpec)
        val wanted = (w / 2 + 1.4f * labelSize() + below(w)).toInt()
        setMeasuredDimension(w, resolveSize(wanted, heightMeasureSpec))
    }

    private fun labelSize() = 12f * resources.displayMetrics.scaledDensity

    /** The map's rectangle in the view (left, top, width, height): centred, twice as wide as high, labels above and below. */
    private fun mapBounds(): FloatArray {
        val label = labelSize()
        val top = 1.4f * label
        val mapH = minOf(height - below(width) - top, width / 2f)
        return floatArrayOf((width - 2 * mapH) / 2, top, 2 * mapH, mapH)
    }

    /** The centre of [cell] in view coordinates (for tests that read the picture back). */
    internal fun cellCenter(cell: Int): android.graphics.PointF {
        val (left, top, w, h) = mapBounds()
        val band = cell / DirectionCoverage.SECTORS
        val sector = cell % DirectionCoverage.SECTORS
        return android.graphics.PointF(left + (sector + 0.5f) * w / DirectionCoverage.SECTORS, top + (DirectionCoverage.BANDS - 0.5f - band) * h / DirectionCoverage.BANDS)
    }

    override fun onDraw(canvas: Canvas) {
        val label = labelSize()
        text.textSize = label
        text.color = MaterialColors.getColor(this, android.R.attr.textColorSecondary)
        grid.color = MaterialColors.getColor(this, com.google.android.material.R.attr.colorOutlineVariant)
        grid.strokeWidth = resources.displayMetrics.density
        val primary = MaterialColors.getColor(this, com.google.android.material.R.attr.colorPrimary)
        val empty = MaterialColors.getColor(this, com.google.android.material.R.attr.colorSurfaceContainerHighest)
        val (left, top, mapW, mapH) = mapBounds()
        val cw = mapW / DirectionCoverage.SECTORS
        val ch = mapH / DirectionCoverage.BANDS
        val most = hits.maxOrNull()?.coerceAtLeast(1) ?: 1
        for (band in 0 until DirectionCoverage.BANDS) for (sector in 0 until DirectionCoverage.SECTORS) {
            val n = hits[band * DirectionCoverage.SECTORS + sector]
            // Band 0 is z = −1 … : drawn at the bottom.
            cell.set(left + sector * cw, top + (DirectionCoverage.BANDS - 1 - band) * ch, left + (sector + 1) * cw, top + (DirectionCoverage.BANDS - band) * ch)
            fill.color = if (n == 0) empty else blend(primary, 0.45f + 0.55f * minOf(1f, n.toFloat() / most * 4f))
            canvas.drawRect(cell, fill)
            canvas.drawRect(cell, grid)
        }
        canvas.drawText(context.getString(dev.motionfusion.app.R.string.calibration_map_top), width / 2f, top - 0.4f * label, text)
                // Longitude atan2(y, x): −π at the left edge, 0 (+x) in the middle.
        val ticks = listOf("−x", "−y", "+x", "+y", "−x")
        for ((i, t) in ticks.withIndex()) {
            val x = left + i * mapW / 4
            text.textAlign = when (i) { 0 -> Paint.Align.LEFT; 4 -> Paint.Align.RIGHT; else -> Paint.Align.CENTER }
            canvas.drawText(t, x, top + mapH + 1.2f * label, text)
        }
        text.textAlign = Paint.Align.CENTER
        captionPaint.color = text.color
        canvas.save()
        canvas.translate(0f, top + mapH + 1.5f * label)
        caption(width).draw(canvas)
        canvas.restore()
    }

    private fun blend(color: Int, alpha: Float): Int = (color and 0x00FFFFFF) or ((alpha * 255).toInt().coerceIn(0, 255) shl 24)
}
