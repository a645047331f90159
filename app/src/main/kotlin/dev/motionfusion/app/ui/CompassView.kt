package dev.motionfusion.app.ui

import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import com.google.android.material.R as MaterialR
import dev.motionfusion.app.R
import kotlin.math.cos
import kotlin.math.sin

/**
 * A compass card: the dial turns so that N points to magnetic north, with the fixed lubber line
 * at the top showing the heading of the screen's top edge. Greyed out when the heading is not
 * magnetic: in 6D (relative) the card shows degrees from the start instead of cardinal points,
 * with tilt only (no heading) it is dimmed; its rim turns amber when the magnetometer is
 * unreliable.
 */
class CompassView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : DialView(context, attrs) {
    private var headingDeg = 0f
    private var state = State.NONE

    /** How far the heading can be trusted. */
    enum class State { NONE, RELATIVE, WARNING, OK }

    private val face = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorSurface, Color.WHITE) }
    private val rimColour = themeColor(MaterialR.attr.colorOutline, Color.GRAY)
    private val warningColour = context.getColor(R.color.warning)
    private val rim = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = rimColour; strokeWidth = dp(3f); style = Paint.Style.STROKE }
    private val tick = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorOnSurfaceVariant, Color.GRAY); strokeWidth = dp(1.5f) }
    private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = themeColor(MaterialR.attr.colorOnSurface, Color.BLACK); textSize = sp(16f); textAlign = Paint.Align.CENTER
    }
    private val north = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = context.getColor(R.color.compass_north); textSize = sp(18f); textAlign = Paint.Align.CENTER; isFakeBoldText = true
    }
    private val lubber = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorPrimary, Color.BLUE) }
    private val marker = Path()

    /** Shows [headingDeg] (0..360 from magnetic north, clockwise) in [state]. */
    fun setHeading(headingDeg: Double, state: State) {
        this.headingDeg = headingDeg.toFloat()
        this.state = state
        invalidate()
    }

    override fun drawDial(canvas: Canvas, cx: Float, cy: Float, r: Float) {
        canvas.drawCircle(cx, cy, r, face)
        rim.color = if (state == State.WARNING) warningColour else rimColour
        canvas.drawCircle(cx, cy, r, rim)
        val alpha = if (state == State.NONE || state == State.RELATIVE) 0x70 else 0xFF
        tick.alpha = alpha; text.alpha = alpha; north.alpha = alpha
        canvas.save()
        canvas.rotate(-headingDeg, cx, cy)
        for (d in 0 until 360 step 10) {
            val a = Math.toRadians(d.toDouble())
            val inner = if (d % 30 == 0) r * 0.82f else r * 0.88f
            val s = sin(a).toFloat()
            val c = cos(a).toFloat()
            canvas.drawLine(cx + s * inner, cy - c * inner, cx + s * r * 0.95f, cy - c * r * 0.95f, tick)
        }
        // A relative heading has no north: degrees instead of cardinal points.
        val labels = if (state == State.RELATIVE) RELATIVE_LABELS else cardinals
        for (i in 0 until 4) {
            val a = Math.toRadians(i * 90.0)
            val lr = r * 0.64f
            val x = cx + sin(a).toFloat() * lr
            val y = cy - cos(a).toFloat() * lr + dp(6f)
            canvas.save()
            canvas.rotate(i * 90f, x, y - dp(6f))
            canvas.drawText(labels[i], x, y, if (i == 0 && state != State.RELATIVE) north else text)
            canvas.restore()
        }
        canvas.restore()
        // Lubber line: the direction the screen's top edge points.
        marker.rewind()
        marker.moveTo(cx, cy - r + dp(2f))
        marker.lineTo(cx - dp(8f), cy - r + dp(18f))
        marker.lineTo(cx + dp(8f), cy - r + dp(18f))
        marker.close()
        canvas.drawPath(marker, lubber)
        canvas.drawCircle(cx, cy, dp(3f), lubber)
    }


    /** The cardinal points' text size, px (follows the font scale). */
    internal val labelTextPx: Float get() = text.textSize

    private val cardinals = cardinalPoints(context)

    private companion object {
        val RELATIVE_LABELS = arrayOf("0", "90", "180", "270")
    }
}
