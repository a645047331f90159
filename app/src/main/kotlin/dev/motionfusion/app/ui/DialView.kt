package dev.motionfusion.app.ui

import android.content.Context
import android.util.TypedValue
import dev.motionfusion.app.R
import android.graphics.Canvas
import android.util.AttributeSet
import android.view.View
import kotlin.math.min

/** Largest side of a round instrument, so that landscape leaves room for the rest of the screen. */
internal const val MAX_DIAL_DP = 260f

/** A round instrument: square, as wide as it is given but at most [MAX_DIAL_DP]. */
abstract class DialView(context: Context, attrs: AttributeSet?) : View(context, attrs) {

    final override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val w = MeasureSpec.getSize(widthMeasureSpec)
        setMeasuredDimension(w, resolveSize(min(w, dp(MAX_DIAL_DP).toInt()), heightMeasureSpec))
    }

    final override fun onDraw(canvas: Canvas) {
        val cx = width / 2f
        val cy = height / 2f
        val r = min(cx, cy) - dp(4f)
        if (r > 0f) drawDial(canvas, cx, cy, r)
    }

    /** Draws the instrument as a circle of radius [r] px about ([cx], [cy]), inset for its rim. */
    protected abstract fun drawDial(canvas: Canvas, cx: Float, cy: Float, r: Float)

    /** [v] density-independent pixels in pixels. */
    protected fun dp(v: Float): Float = v * resources.displayMetrics.density
}

/** [v] scale-independent pixels in pixels: text that follows the user's font size (non-linearly from Android 14). */
internal fun View.sp(v: Float): Float = TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, v, resources.displayMetrics)

/** N, E, S, W in the resources' language. */
internal fun cardinalPoints(c: Context): Array<String> = arrayOf(
    c.getString(R.string.cardinal_north), c.getString(R.string.cardinal_east), c.getString(R.string.cardinal_south), c.getString(R.string.cardinal_west),
)
