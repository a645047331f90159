package dev.motionfusion.app.ui

import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import com.google.android.material.R as MaterialR

/**
 * An artificial horizon: sky and ground as seen from the phone flown with the screen's top edge
 * as its nose. The horizon moves down as the nose rises ([pitchDeg] > 0) and turns opposite to
 * the bank ([rollDeg] > 0: right edge down). A fixed symbol marks the phone; a ladder marks
 * every 10° of pitch. Draws nothing per frame that allocates.
 */
class AttitudeIndicatorView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : DialView(context, attrs) {
    private var pitchDeg = 0f
    private var rollDeg = 0f
    private var valid = false

    private val sky = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = Color.rgb(0x2E, 0x6F, 0xB0) }
    private val ground = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = Color.rgb(0x7A, 0x52, 0x30) }
    private val line = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = Color.WHITE; strokeWidth = dp(2f); style = Paint.Style.STROKE }
    private val ladder = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = Color.WHITE; strokeWidth = dp(1.2f); textSize = sp(11f) }
    private val symbol = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        color = Color.rgb(0xFF, 0xC1, 0x07); strokeWidth = dp(4f); style = Paint.Style.STROKE; strokeCap = Paint.Cap.ROUND
    }
    private val rim = Paint(Paint.ANTI_ALIAS_FLAG).apply { color = themeColor(MaterialR.attr.colorOutline, Color.GRAY); strokeWidth = dp(3f); style = Paint.Style.STROKE }
    private val dim = Paint().apply { color = themeColor(MaterialR.attr.colorSurface, Color.BLACK); alpha = 0xB0 }
    private val clip = Path()

    /** The pitch ladder's text size, px (follows the font scale). */
    internal val labelTextPx: Float get() = ladder.textSize

    /** Shows [pitchDeg] and [rollDeg] (aerospace signs), or "no attitude" when [valid] is false. */
    fun setAttitude(pitchDeg: Double, rollDeg: Double, valid: Boolean) {
        this.pitchDeg = pitchDeg.toFloat()
        this.rollDeg = rollDeg.toFloat()
        this.valid = valid
        invalidate()
    }

    override fun drawDial(canvas: Canvas, cx: Float, cy: Float, r: Float) {
        clip.rewind()
        clip.addCircle(cx, cy, r, Path.Direction.CW)
        canvas.save()
        canvas.clipPath(clip)
        // Pixels per degree of pitch: ±40° fills the dial.
        val ppd = r / 40f
        canvas.save()
        canvas.rotate(-rollDeg, cx, cy)
        val horizonY = cy + pitchDeg * ppd
        val big = r * 4f
        canvas.drawRect(cx - big, cy - big - 2000f, cx + big, horizonY, sky)
        canvas.drawRect(cx - big, horizonY, cx + big, cy + big + 2000f, ground)
        canvas.drawLine(cx - big, horizonY, cx + big, horizonY, line)
        var p = -90
        while (p <= 90) {
            if (p != 0) {
                val y = horizonY - p * ppd
                if (y > cy - r && y < cy + r) {
                    val half = if (p % 20 == 0) r * 0.28f else r * 0.14f
                    canvas.drawLine(cx - half, y, cx + half, y, ladder)
                    if (p % 20 == 0) canvas.drawText(p.toString(), cx + half + dp(4f), y + dp(4f), ladder)
                }
            }
            p += 10
        }
        canvas.restore()
        if (!valid) canvas.drawRect(cx - r, cy - r, cx + r, cy + r, dim)
        canvas.restore()
        // The phone's symbol: wings and a centre dot, fixed.
        canvas.drawLine(cx - r * 0.55f, cy, cx - r * 0.18f, cy, symbol)
        canvas.drawLine(cx + r * 0.18f, cy, cx + r * 0.55f, cy, symbol)
        canvas.drawLine(cx - r * 0.18f, cy, cx, cy + r * 0.1f, symbol)
        canvas.drawLine(cx, cy + r * 0.1f, cx + r * 0.18f, cy, symbol)
        canvas.drawCircle(cx, cy, r, rim)
    }
}
