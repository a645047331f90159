package dev.motionfusion.app.calibration

import android.content.Context
import android.graphics.Canvas
import android.graphics.Paint
import android.graphics.RectF
import android.util.AttributeSet
import android.view.View
import com.google.android.material.color.MaterialColors
import dev.motionfusion.app.R

/**
 * The six faces of the accelerometer step as tiles, each with the phone drawn in that pose on a
 * table line: held faces ticked, the face asked for outlined in the primary colour.
 */
class PoseFacesView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    private var held: Set<PoseFace> = emptySet()
    private var asked: PoseFace? = null
    private val paint = Paint(Paint.ANTI_ALIAS_FLAG)
    private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply { textAlign = Paint.Align.CENTER }
    private val r = RectF()

    init {
        // Read before the first pose too: none held.
        contentDescription = resources.getQuantityString(R.plurals.calibration_faces_description, 0, 0)
    }

    fun setFaces(held: Set<PoseFace>, asked: PoseFace?) {
        if (held == this.held && asked == this.asked) return
        this.held = held
        this.asked = asked
        val heldText = resources.getQuantityString(R.plurals.calibration_faces_description, held.size, held.size)
        contentDescription = asked?.let { context.getString(R.string.calibration_faces_next, heldText, context.getString(faceName(it))) } ?: heldText
        invalidate()
    }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val w = MeasureSpec.getSize(widthMeasureSpec)
        setMeasuredDimension(w, resolveSize((w * 0.62f).toInt(), heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        val d = resources.displayMetrics.density
        val primary = MaterialColors.getColor(this, com.google.android.material.R.attr.colorPrimary)
        val onSurface = MaterialColors.getColor(this, com.google.android.material.R.attr.colorOnSurface)
        val container = MaterialColors.getColor(this, com.google.android.material.R.attr.colorSurfaceContainerHigh)
        val doneFill = MaterialColors.getColor(this, com.google.android.material.R.attr.colorPrimaryContainer)
        val outline = MaterialColors.getColor(this, com.google.android.material.R.attr.colorOutlineVariant)
        val body = MaterialColors.getColor(this, com.google.android.material.R.attr.colorOutline)
        val cols = 3
        val gap = 8 * d
        val tw = (width - (cols + 1) * gap) / cols
        val th = (height - 3 * gap) / 2
        text.textSize = minOf(14 * resources.displayMetrics.scaledDensity, tw / 9f)
        for ((i, face) in PoseFace.entries.withIndex()) {
            val x0 = gap + (i % cols) * (tw + gap)
            val y0 = gap + (i / cols) * (th + gap)
            r.set(x0, y0, x0 + tw, y0 + th)
            paint.style = Paint.Style.FILL
            paint.color = if (face in held) doneFill else container
            canvas.drawRoundRect(r, 12 * d, 12 * d, paint)
            paint.style = Paint.Style.STROKE
            paint.strokeWidth = (if (face == asked) 3 else 1) * d
            paint.color = if (face == asked) primary else outline
            canvas.drawRoundRect(r, 12 * d, 12 * d, paint)
            drawPhone(canvas, face, x0 + tw / 2, y0 + th * 0.45f, minOf(tw, th) * 0.5f, body, primary, onSurface)
            text.color = onSurface
            canvas.drawText(context.getString(faceName(face)), x0 + tw / 2, y0 + th - 0.6f * text.textSize, text)
            if (face in held) {
                text.color = primary
                text.textSize *= 1.6f
                canvas.drawText("✓", x0 + tw - 1.0f * text.textSize, y0 + 1.3f * text.textSize, text)
                text.textSize /= 1.6f
            }
        }
    }

    /** The phone in [face]'s pose resting on a table line, [size] its long side; the screen side drawn in [screen]. */
    private fun drawPhone(c: Canvas, face: PoseFace, cx: Float, cy: Float, size: Float, ink: Int, screen: Int, table: Int) {
        val d = resources.displayMetrics.density
        val long = size
        val short = size * 0.5f
        val thin = size * 0.12f
        paint.style = Paint.Style.FILL
        // Width and height of the drawn outline; the table line is under it.
        val (w, h) = when (face) {
            PoseFace.SCREEN_UP, PoseFace.SCREEN_DOWN -> long to thin // side view of a phone lying flat
            PoseFace.BOTTOM_EDGE_DOWN, PoseFace.TOP_EDGE_DOWN -> short to long // front view, standing
            PoseFace.LEFT_EDGE_DOWN, PoseFace.RIGHT_EDGE_DOWN -> long to short // front view, on its side
        }
        val base = cy + long / 2
        r.set(cx - w / 2, base - h, cx + w / 2, base)
        paint.color = ink
        c.drawRoundRect(r, 3 * d, 3 * d, paint)
        paint.color = screen
        when (face) {
            PoseFace.SCREEN_UP -> c.drawRect(r.left + 3 * d, r.top - 3 * d, r.right - 3 * d, r.top + 1 * d, paint)
            PoseFace.SCREEN_DOWN -> c.drawRect(r.left + 3 * d, r.bottom - 2 * d, r.right - 3 * d, r.bottom + 1 * d, paint)
            else -> {
                // The screen faces the viewer; a dot marks the top edge (the earpiece).
                val inset = 0.08f * short
                c.drawRect(r.left + inset, r.top + inset, r.right - inset, r.bottom - inset, paint)
                paint.color = ink
                val dot = 0.08f * long
                val (dx, dy) = when (face) {
                    PoseFace.BOTTOM_EDGE_DOWN -> 0f to -(h / 2 - inset / 2)
                    PoseFace.TOP_EDGE_DOWN -> 0f to (h / 2 - inset / 2)
                    PoseFace.LEFT_EDGE_DOWN -> -(w / 2 - inset / 2) to 0f // +x up: the top edge points left
                    else -> (w / 2 - inset / 2) to 0f
                }
                c.drawCircle(r.centerX() + dx, r.centerY() + dy, dot / 2, paint)
            }
        }
        paint.color = table
        paint.strokeWidth = 2 * d
        c.drawLine(cx - long * 0.7f, base + 4 * d, cx + long * 0.7f, base + 4 * d, paint)
    }

    companion object {
        fun faceName(face: PoseFace): Int = when (face) {
            PoseFace.SCREEN_UP -> R.string.calibration_face_screen_up
            PoseFace.SCREEN_DOWN -> R.string.calibration_face_screen_down
            PoseFace.BOTTOM_EDGE_DOWN -> R.string.calibration_face_bottom_down
            PoseFace.TOP_EDGE_DOWN -> R.string.calibration_face_top_down
            PoseFace.LEFT_EDGE_DOWN -> R.string.calibration_face_left_down
            PoseFace.RIGHT_EDGE_DOWN -> R.string.calibration_face_right_down
        }
    }
}
